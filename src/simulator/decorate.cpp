#include "decorate.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace seqtopo::simulator::detail {
namespace {

Colour pick(const std::vector<Colour>& colours, Rng& rng) {
  return colours.empty() ? rgb(200, 60, 60)
                         : colours[static_cast<std::size_t>(rng.below(static_cast<int>(colours.size())))];
}

Decal on_run(const FaceRun& run, double u0, double u1, double z0, double z1) {
  Decal d;
  d.side = run.side;
  d.plane = run.plane;
  d.u0 = u0;
  d.u1 = u1;
  d.z0 = z0;
  d.z1 = z1;
  return d;
}

}  // namespace

std::vector<FaceRun> face_runs(const GridWorld& w, Rect region, double min_height) {
  std::vector<FaceRun> runs;
  const double c = w.cell_size();
  const double x0 = w.bounds().x0, y0 = w.bounds().y0;
  auto in_region = [&](int cx, int cy) {
    const double x = x0 + (cx + 0.5) * c, y = y0 + (cy + 0.5) * c;
    return x >= region.x0 && x <= region.x1 && y >= region.y0 && y <= region.y1;
  };
  auto exposed = [&](int cx, int cy, int nx, int ny) {
    return w.solid(cx, cy) && w.material(w.material_at(cx, cy)).height >= min_height && w.inside(nx, ny) &&
           !w.solid(nx, ny) && in_region(nx, ny);
  };
  // Faces along x (north/south) then along y (east/west).
  for (int cy = 0; cy < w.rows(); ++cy) {
    for (const auto& [side, dy] : {std::pair{Side::north, 1}, std::pair{Side::south, -1}}) {
      int start = -1;
      for (int cx = 0; cx <= w.columns(); ++cx) {
        const bool e = cx < w.columns() && exposed(cx, cy, cx, cy + dy);
        if (e && start < 0) start = cx;
        if (!e && start >= 0) {
          runs.push_back({side, y0 + (cy + (dy > 0 ? 1 : 0)) * c, x0 + start * c, x0 + cx * c});
          start = -1;
        }
      }
    }
  }
  for (int cx = 0; cx < w.columns(); ++cx) {
    for (const auto& [side, dx] : {std::pair{Side::east, 1}, std::pair{Side::west, -1}}) {
      int start = -1;
      for (int cy = 0; cy <= w.rows(); ++cy) {
        const bool e = cy < w.rows() && exposed(cx, cy, cx + dx, cy);
        if (e && start < 0) start = cy;
        if (!e && start >= 0) {
          runs.push_back({side, x0 + (cx + (dx > 0 ? 1 : 0)) * c, y0 + start * c, y0 + cy * c});
          start = -1;
        }
      }
    }
  }
  return runs;
}

DecorStyle office_style() {
  DecorStyle s;
  s.door_colours = {rgb(150, 100, 60), rgb(120, 80, 50), rgb(180, 140, 90), rgb(90, 110, 140), rgb(200, 200, 195)};
  s.colours = {rgb(210, 40, 40),  rgb(40, 90, 200),  rgb(240, 200, 40),  rgb(40, 160, 70), rgb(230, 120, 30),
               rgb(140, 60, 170), rgb(30, 170, 180), rgb(235, 110, 160), rgb(110, 70, 40), rgb(20, 20, 30)};
  return s;
}

DecorStyle facade_style() {
  DecorStyle s;
  s.outdoor = true;
  s.spacing = 1.2;
  s.doors = 0.6;
  s.posters = 0.3;
  s.patches = 0.6;
  s.bars = 0.8;
  s.boards = 0;
  s.small = 0;
  s.windows = 4;
  s.door_colours = {rgb(70, 70, 80), rgb(140, 40, 30), rgb(40, 80, 60)};
  s.colours = {rgb(200, 40, 40), rgb(30, 80, 180), rgb(230, 190, 30), rgb(30, 140, 70), rgb(240, 240, 240)};
  return s;
}

double place_item(GridWorld& world, const FaceRun& run, double u, int kind, const DecorStyle& style, Rng& rng,
                  double max_width) {
  switch (kind) {
    case 0: {  // door in a frame
      const double w = style.outdoor ? 1.4 : 0.95;
      if (w > max_width) return 0;
      Decal d = on_run(run, u, u + w, 0.0, style.outdoor ? 2.4 : 2.08);
      d.fill = pick(style.door_colours, rng);
      d.border = rng.chance(0.5) ? rgb(245, 245, 240) : rgb(45, 40, 40);
      d.border_width = 0.08;
      world.add_decal(d);
      return w;
    }
    case 1: {  // poster
      const double w = rng.uniform(0.45, 0.85);
      if (w > max_width) return 0;
      const double z0 = rng.uniform(1.05, 1.3);
      Decal d = on_run(run, u, u + w, z0, z0 + w * rng.uniform(1.1, 1.45));
      d.fill = pick(style.colours, rng);
      d.border = pick(style.colours, rng);
      d.style = DecalStyle::bands;
      world.add_decal(d);
      return w;
    }
    case 2: {  // colour patch: a painted panel
      const double w = std::min(max_width, rng.uniform(1.0, 2.6));
      if (w < 0.8) return 0;
      const bool full = rng.chance(0.5);
      Decal d = on_run(run, u, u + w, full ? 0.12 : rng.uniform(0.8, 1.0), full ? 2.45 : rng.uniform(1.6, 2.0));
      d.fill = pick(style.colours, rng);
      d.border = pick(style.colours, rng);
      d.style = rng.chance(0.3) ? DecalStyle::split : DecalStyle::solid;
      if (style.outdoor) {
        d.z0 = rng.uniform(2.6, 3.0);
        d.z1 = d.z0 + rng.uniform(0.5, 0.9);
      }
      world.add_decal(d);
      return w;
    }
    case 3: {  // vertical bar: pilaster, pipe, cable duct
      const double w = rng.uniform(0.08, 0.22);
      if (w > max_width) return 0;
      Decal d = on_run(run, u, u + w, 0.0, style.outdoor ? 12.0 : 2.6);
      d.fill = rng.chance(0.5) ? rgb(60, 60, 65) : rgb(235, 235, 235);
      world.add_decal(d);
      return w;
    }
    case 4: {  // notice board with pinned sheets
      const double w = rng.uniform(1.0, 1.6);
      if (w > max_width) return 0;
      Decal d = on_run(run, u, u + w, 1.0, 1.85);
      d.fill = rgb(185, 140, 90);
      d.border = rgb(120, 80, 40);
      d.border_width = 0.04;
      d.style = DecalStyle::bands;
      world.add_decal(d);
      return w;
    }
    case 5: {  // fire extinguisher / hose box: small, red
      const double w = rng.uniform(0.22, 0.5);
      if (w > max_width) return 0;
      const double z0 = rng.uniform(0.3, 1.0);
      Decal d = on_run(run, u, u + w, z0, z0 + w * 1.4);
      d.fill = rgb(215, 25, 25);
      d.border = rgb(240, 240, 240);
      d.border_width = 0.03;
      world.add_decal(d);
      return w;
    }
    case 6: {  // window: ground-floor and upper rows on facades
      const double w = rng.uniform(1.0, 1.6);
      if (w > max_width) return 0;
      for (double z = 0.9; z + 1.4 < 12.0; z += 3.2) {
        Decal d = on_run(run, u, u + w, z, z + 1.4);
        d.fill = rgb(70, 105, 140);
        d.border = rgb(230, 230, 225);
        d.border_width = 0.07;
        d.style = DecalStyle::solid;
        world.add_decal(d);
      }
      return w;
    }
    default:
      return 0;
  }
}

void decorate(GridWorld& world, Rect region, const DecorStyle& style, Rng& rng) {
  const std::vector<double> weights{style.doors,  style.posters, style.patches, style.bars,
                                    style.boards, style.small,   style.windows};
  double total = 0;
  for (double w : weights) total += w;
  if (total <= 0) return;
  for (const FaceRun& run : face_runs(world, region)) {
    if (run.u1 - run.u0 < 0.6) continue;
    double u = run.u0 + rng.uniform(0.2, style.spacing);
    while (u < run.u1 - 0.3) {
      double r = rng.uniform() * total;
      int kind = 0;
      while (kind + 1 < static_cast<int>(weights.size()) && r >= weights[static_cast<std::size_t>(kind)]) {
        r -= weights[static_cast<std::size_t>(kind)];
        ++kind;
      }
      const double width = place_item(world, run, u, kind, style, rng, run.u1 - 0.15 - u);
      u += width + rng.uniform(0.3, 2.0 * style.spacing);
    }
  }
}

}  // namespace seqtopo::simulator::detail
