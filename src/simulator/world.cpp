#include "seqtopo/simulator/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "seqtopo/simulator/random.hpp"

namespace seqtopo::simulator {
namespace {

// Value noise in [0, 1) of integer lattice coordinates: textures vary but never change between frames.
float lattice(std::int64_t a, std::int64_t b, std::uint64_t salt) {
  const std::uint64_t h =
      hash_combine(hash_combine(static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b)), salt);
  return static_cast<float>(h >> 40) * (1.0F / 16777216.0F);
}

std::int64_t cell_of(double v, double size) { return static_cast<std::int64_t>(std::floor(v / size)); }
double frac(double v) { return v - std::floor(v); }

Colour scale(Colour c, float s) { return {c[0] * s, c[1] * s, c[2] * s}; }
Colour mix(Colour a, Colour b, float t) {
  return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}

std::uint64_t face_key(std::size_t cell, Side side) {
  return static_cast<std::uint64_t>(cell) * 4U + static_cast<std::uint64_t>(side);
}

// A surface pattern at texture coordinates (u, v) [m]; v is the height on walls.
Colour pattern_colour(Pattern pattern, Colour base, Colour accent, double period, double u, double v, double height,
                      std::uint64_t salt) {
  switch (pattern) {
    case Pattern::plain: {
      if (v < 0.12) return accent;  // skirting board
      const float n = lattice(cell_of(u, 0.5), cell_of(v, 0.5), salt);
      return scale(base, 0.97F + 0.06F * n);
    }
    case Pattern::brick: {
      const double course_h = 0.075, brick_w = 0.22;
      const auto course = cell_of(v, course_h);
      const double shifted = u + (course % 2 == 0 ? 0.0 : brick_w / 2);
      if (frac(v / course_h) < 0.16 || frac(shifted / brick_w) < 0.06) return accent;
      return scale(base, 0.82F + 0.3F * lattice(cell_of(shifted, brick_w), course, salt));
    }
    case Pattern::panels: {
      if (frac(u / period) < 0.04) return accent;
      return scale(base, 0.93F + 0.12F * lattice(cell_of(u, period), 0, salt));
    }
    case Pattern::glass: {
      if (frac(u / period) < 0.06 || std::abs(v - 1.0) < 0.05 || v < 0.3 || v > height - 0.1) return accent;
      return scale(base, static_cast<float>(0.75 + 0.35 * std::min(1.0, v / std::max(height, 1.0))));
    }
    case Pattern::tiles: {
      if (frac(u / period) < 0.05 || frac(v / period) < 0.05) return accent;
      return scale(base, 0.96F + 0.08F * lattice(cell_of(u, period), cell_of(v, period), salt));
    }
    case Pattern::foliage: {
      const float n = lattice(cell_of(u, 0.09), cell_of(v, 0.09), salt);
      const float m = lattice(cell_of(u, 0.35), cell_of(v, 0.35), salt + 1);
      return scale(mix(base, accent, m * 0.6F), 0.65F + 0.6F * n);
    }
    case Pattern::tree: {
      if (v < 2.2) return scale(accent, 0.8F + 0.35F * lattice(cell_of(u, 0.05), cell_of(v, 0.3), salt));
      return pattern_colour(Pattern::foliage, base, scale(base, 0.6F), period, u, v, height, salt);
    }
    case Pattern::stripes:
      return frac(u / period) < 0.5 ? base : accent;
    case Pattern::concrete: {
      const float n = lattice(cell_of(u, 0.4), cell_of(v, 0.4), salt);
      const float f = lattice(cell_of(u, 0.05), cell_of(v, 0.05), salt + 7);
      if (frac(u / period) < 0.015 || frac(v / period) < 0.015) return accent;  // formwork joints
      return scale(base, 0.85F + 0.15F * n + 0.08F * f);
    }
  }
  return base;
}

Colour decal_colour(const Decal& d, double u, double z) {
  const double b = d.border_width;
  if (b > 0 && (u - d.u0 < b || d.u1 - u < b || z - d.z0 < b || d.z1 - z < b)) return d.border;
  switch (d.style) {
    case DecalStyle::solid:
      return d.fill;
    case DecalStyle::bands: {
      // A picture in the top half, lines of text below.
      const double top = d.z0 + 0.5 * (d.z1 - d.z0);
      if (z >= top) return d.fill;
      return static_cast<int>(std::floor((top - z) / 0.07)) % 2 == 0 ? mix(d.fill, d.border, 0.7F) : rgb(235, 235, 228);
    }
    case DecalStyle::split:
      return u < 0.5 * (d.u0 + d.u1) ? d.fill : d.border;
  }
  return d.fill;
}

}  // namespace

GridWorld::GridWorld(Rect bounds, double cell_size) : bounds_(bounds), cell_(cell_size) {
  if (!(cell_size > 0) || !(bounds.x1 > bounds.x0) || !(bounds.y1 > bounds.y0)) {
    throw std::invalid_argument("a world needs a positive cell size and non-empty bounds");
  }
  columns_ = static_cast<int>(std::ceil((bounds.x1 - bounds.x0) / cell_));
  rows_ = static_cast<int>(std::ceil((bounds.y1 - bounds.y0) / cell_));
  materials_.assign(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_), 0);
  grounds_.assign(materials_.size(), 0);
  ground_table_.push_back(Ground{});
}

int GridWorld::add_material(const Material& material) {
  if (material_table_.size() >= 65534) throw std::invalid_argument("too many materials");
  material_table_.push_back(material);
  return static_cast<int>(material_table_.size());
}

int GridWorld::add_ground(const Ground& ground) {
  if (ground_table_.size() >= 255) throw std::invalid_argument("too many grounds");
  // The constructor's placeholder is replaced by the first ground a scenario adds.
  if (ground_table_.size() == 1 && !first_ground_set_) {
    ground_table_[0] = ground;
    first_ground_set_ = true;
    return 0;
  }
  ground_table_.push_back(ground);
  return static_cast<int>(ground_table_.size()) - 1;
}

int GridWorld::cell_x(double x) const { return static_cast<int>(std::floor((x - bounds_.x0) / cell_)); }
int GridWorld::cell_y(double y) const { return static_cast<int>(std::floor((y - bounds_.y0) / cell_)); }
bool GridWorld::solid_at(Vec2 p) const { return solid(cell_x(p.x), cell_y(p.y)); }

namespace {
template <typename F>
void for_cells_in(const GridWorld& w, Rect r, F&& f) {
  const double c = w.cell_size();
  const int x0 = std::max(0, static_cast<int>(std::ceil((r.x0 - w.bounds().x0) / c - 0.5)));
  const int x1 = std::min(w.columns() - 1, static_cast<int>(std::floor((r.x1 - w.bounds().x0) / c - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::ceil((r.y0 - w.bounds().y0) / c - 0.5)));
  const int y1 = std::min(w.rows() - 1, static_cast<int>(std::floor((r.y1 - w.bounds().y0) / c - 0.5)));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) f(x, y);
  }
}
}  // namespace

void GridWorld::fill(Rect area, int material) {
  if (material < 1 || material > static_cast<int>(material_table_.size()))
    throw std::invalid_argument("unknown material");
  for_cells_in(*this, area, [&](int x, int y) { materials_[index(x, y)] = static_cast<std::uint16_t>(material); });
}

void GridWorld::carve(Rect area, int ground) {
  if (ground < 0 || ground >= static_cast<int>(ground_table_.size())) throw std::invalid_argument("unknown ground");
  for_cells_in(*this, area, [&](int x, int y) {
    materials_[index(x, y)] = 0;
    grounds_[index(x, y)] = static_cast<std::uint8_t>(ground);
  });
}

void GridWorld::carve_corridor(Vec2 a, Vec2 b, double width, int ground) {
  const double h = width / 2;
  if (a.x == b.x || a.y == b.y) {
    carve({std::min(a.x, b.x) - h, std::min(a.y, b.y) - h, std::max(a.x, b.x) + h, std::max(a.y, b.y) + h}, ground);
    return;
  }
  const Vec2 d = b - a;
  const double len2 = dot(d, d);
  for_cells_in(*this, {std::min(a.x, b.x) - h, std::min(a.y, b.y) - h, std::max(a.x, b.x) + h, std::max(a.y, b.y) + h},
               [&](int x, int y) {
                 const Vec2 p{bounds_.x0 + (x + 0.5) * cell_, bounds_.y0 + (y + 0.5) * cell_};
                 const double t = std::clamp(dot(p - a, d) / len2, 0.0, 1.0);
                 if (distance(p, a + t * d) <= h) {
                   materials_[index(x, y)] = 0;
                   grounds_[index(x, y)] = static_cast<std::uint8_t>(ground);
                 }
               });
}

void GridWorld::add_decal(const Decal& decal) {
  if (!(decal.u1 > decal.u0) || !(decal.z1 > decal.z0))
    throw std::invalid_argument("a decal needs u1 > u0 and z1 > z0");
  const auto id = static_cast<std::uint32_t>(decals_.size());
  decals_.push_back(decal);
  const bool x_plane = decal.side == Side::west || decal.side == Side::east;
  // The solid cells whose face lies in the decal's plane: the plane is the cell's west edge for a
  // west face, its east edge for an east face, and so on.
  const double offset = (decal.side == Side::west || decal.side == Side::south) ? 0.5 * cell_ : -0.5 * cell_;
  const int across = x_plane ? cell_x(decal.plane + offset) : cell_y(decal.plane + offset);
  const double origin = x_plane ? bounds_.y0 : bounds_.x0;
  const int first = static_cast<int>(std::floor((decal.u0 - origin) / cell_));
  const int last = static_cast<int>(std::floor((decal.u1 - origin) / cell_ - 1e-9));
  for (int k = first; k <= last; ++k) {
    const int cx = x_plane ? across : k;
    const int cy = x_plane ? k : across;
    if (!inside(cx, cy)) continue;
    face_decals_[face_key(index(cx, cy), decal.side)].push_back(id);
  }
}

const std::vector<std::uint32_t>* GridWorld::decals_on(int cx, int cy, Side side) const {
  if (face_decals_.empty()) return nullptr;
  const auto it = face_decals_.find(face_key(index(cx, cy), side));
  return it == face_decals_.end() ? nullptr : &it->second;
}

Colour GridWorld::wall_colour(int cx, int cy, Side side, double u, double z) const {
  return face_colour(face(cx, cy, side), u, z);
}

Colour GridWorld::face_colour(const Face& face, double u, double z) const {
  if (const auto* list = face.decals) {
    // Later decals are painted over earlier ones.
    for (auto it = list->rbegin(); it != list->rend(); ++it) {
      const Decal& d = decals_[*it];
      if (u >= d.u0 && u <= d.u1 && z >= d.z0 && z <= d.z1) return decal_colour(d, u, z);
    }
  }
  const Material& m = material(face.material);
  return pattern_colour(m.pattern, m.base, m.accent, m.period, u, z, m.height,
                        static_cast<std::uint64_t>(face.material));
}

Colour GridWorld::ground_colour(int cx, int cy, Vec2 p) const {
  const Ground& g = ground(ground_at(cx, cy));
  return pattern_colour(g.pattern == Pattern::plain ? Pattern::tiles : g.pattern, g.base, g.accent, g.period, p.x, p.y,
                        1.0, 1000U + ground_at(cx, cy));
}

Colour GridWorld::ceiling_colour(Vec2 p) const {
  // Ceiling tiles with light panels centred on a 2.5 m x 3 m lattice (symmetric about whole metres, so
  // mirrored corridors get the same lights).
  if (std::abs(p.x - 2.5 * std::round(p.x / 2.5)) < 0.3 && std::abs(p.y - 3.0 * std::round(p.y / 3.0)) < 0.6) {
    return rgb(255, 255, 246);
  }
  if (frac(p.x / 0.6) < 0.04 || frac(p.y / 0.6) < 0.04) return scale(ceiling, 0.8F);
  return ceiling;
}

RayHit GridWorld::cast(Vec2 origin, double angle, double max_distance) const {
  RayHit result;
  const double dx = std::cos(angle), dy = std::sin(angle);
  int cx = cell_x(origin.x), cy = cell_y(origin.y);
  if (!inside(cx, cy)) return result;
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double next_x = bounds_.x0 + (cx + (step_x > 0 ? 1 : 0)) * cell_;
  const double next_y = bounds_.y0 + (cy + (step_y > 0 ? 1 : 0)) * cell_;
  double t_max_x = dx != 0 ? (next_x - origin.x) / dx : inf;
  double t_max_y = dy != 0 ? (next_y - origin.y) / dy : inf;
  const double t_delta_x = dx != 0 ? cell_ / std::abs(dx) : inf;
  const double t_delta_y = dy != 0 ? cell_ / std::abs(dy) : inf;
  while (true) {
    double d = 0;
    Side side{};
    if (t_max_x < t_max_y) {
      cx += step_x;
      d = t_max_x;
      t_max_x += t_delta_x;
      side = step_x > 0 ? Side::west : Side::east;
    } else {
      cy += step_y;
      d = t_max_y;
      t_max_y += t_delta_y;
      side = step_y > 0 ? Side::south : Side::north;
    }
    if (d > max_distance || !inside(cx, cy)) return result;
    if (material_at(cx, cy) != 0) {
      result.hit = true;
      result.distance = d;
      result.cx = cx;
      result.cy = cy;
      result.side = side;
      result.point = {origin.x + d * dx, origin.y + d * dy};
      return result;
    }
  }
}

}  // namespace seqtopo::simulator
