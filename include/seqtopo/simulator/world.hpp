#pragma once
// The floor plan of a synthetic world: a grid of square cells, each either free (with a ground surface,
// roofed indoors, open sky outdoors) or solid (a wall, building, pillar, tree or cabinet of some height).
// Wall faces carry a procedural texture of their material plus explicit decals: doors, posters, colour
// patches, windows, vertical bars. A grid keeps ray casting exact and fast (one cell per step) and lets
// scenarios carve corridors along any path graph without polygon clipping.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "seqtopo/simulator/geometry.hpp"

namespace seqtopo::simulator {

using Colour = std::array<float, 3>;  // R G B, 0..255

inline Colour rgb(int r, int g, int b) { return {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)}; }

// Procedural surface patterns; `period` [m] sets their scale.
enum class Pattern : std::uint8_t {
  plain,     // paint with a darker skirting board
  brick,     // courses of bricks with mortar joints
  panels,    // vertical boards: seams every `period`
  glass,     // glazing with mullions every `period` (strong vertical edges)
  tiles,     // square tiles with grout lines every `period`
  foliage,   // leafy noise (hedges)
  tree,      // trunk below 2.2 m, crown above
  stripes,   // vertical stripes of base/accent, half a period each (repeats on purpose)
  concrete,  // coarse grey blotches
};

struct Material {
  Pattern pattern = Pattern::plain;
  Colour base = rgb(200, 200, 200);
  Colour accent = rgb(120, 120, 120);
  double height = 2.6;  // [m]
  double period = 1.0;  // [m]
};

struct Ground {
  Pattern pattern = Pattern::tiles;  // plain, tiles, foliage (grass), concrete (paving) or brick (pavers)
  Colour base = rgb(150, 140, 130);
  Colour accent = rgb(120, 110, 100);
  double period = 0.5;  // [m]
  bool roofed = true;   // indoors: a ceiling at GridWorld::ceiling_height; else sky
};

// A solid cell's face, named by its outward normal.
enum class Side : std::uint8_t { west, east, south, north };

enum class DecalStyle : std::uint8_t {
  solid,  // one colour (colour patch, door panel, pillar bar)
  bands,  // horizontal bands of fill/border colour (poster, notice board)
  split,  // left half fill, right half border colour (two-tone panel)
};

// A rectangle painted on the wall faces that lie in the plane x = plane (sides west/east) or
// y = plane (south/north), covering u in [u0, u1] along the wall (u = y or x) and heights [z0, z1].
struct Decal {
  Side side = Side::north;
  double plane = 0.0;         // [m]
  double u0 = 0.0, u1 = 0.0;  // [m]
  double z0 = 0.0, z1 = 0.0;  // [m]
  Colour fill = rgb(255, 255, 255);
  Colour border = rgb(40, 40, 40);
  double border_width = 0.0;  // [m], frame drawn inside the rectangle
  DecalStyle style = DecalStyle::solid;
};

// The first solid face along a ray.
struct RayHit {
  bool hit = false;
  double distance = 0.0;  // [m] from the ray origin
  int cx = 0, cy = 0;     // the solid cell
  Side side = Side::west;
  Vec2 point;  // [m]
};

class GridWorld {
 public:
  // A world covering `bounds`, initially all free under ground 0 (see add_ground).
  GridWorld(Rect bounds, double cell_size);

  int add_material(const Material& material);  // returns its id (>= 1; 0 means free)
  int add_ground(const Ground& ground);        // returns its id; the first one added (id 0) is the default
  void fill(Rect area, int material);          // cells whose centre lies in `area` become solid
  void carve(Rect area, int ground);           // ... become free with this ground
  // A corridor: every cell within width/2 of the segment a-b (square ends for axis-aligned segments).
  void carve_corridor(Vec2 a, Vec2 b, double width, int ground);
  void add_decal(const Decal& decal);

  int columns() const { return columns_; }
  int rows() const { return rows_; }
  double cell_size() const { return cell_; }
  const Rect& bounds() const { return bounds_; }
  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < columns_ && cy < rows_; }
  int material_at(int cx, int cy) const { return materials_[index(cx, cy)]; }
  int ground_at(int cx, int cy) const { return grounds_[index(cx, cy)]; }
  bool solid(int cx, int cy) const { return inside(cx, cy) && material_at(cx, cy) != 0; }
  bool solid_at(Vec2 p) const;
  int cell_x(double x) const;
  int cell_y(double y) const;
  const Material& material(int id) const { return material_table_.at(static_cast<std::size_t>(id - 1)); }
  const Ground& ground(int id) const { return ground_table_.at(static_cast<std::size_t>(id)); }
  const std::vector<Decal>& decals() const { return decals_; }

  // Ceiling height indoors [m]; walls indoors are at least this high.
  double ceiling_height = 2.6;
  Colour ceiling = rgb(232, 232, 226);
  Colour sky = rgb(150, 190, 235);
  Colour horizon = rgb(215, 225, 235);

  // The first solid face hit by a ray from `origin` along `angle` [rad], within max_distance [m].
  RayHit cast(Vec2 origin, double angle, double max_distance = 1e9) const;

  // Texture of a wall face at position u along the wall and height z [m].
  Colour wall_colour(int cx, int cy, Side side, double u, double z) const;
  // The same in two steps, for renderers that colour many heights of one face.
  struct Face {
    int material = 0;
    const std::vector<std::uint32_t>* decals = nullptr;
  };
  Face face(int cx, int cy, Side side) const { return {material_at(cx, cy), decals_on(cx, cy, side)}; }
  Colour face_colour(const Face& face, double u, double z) const;
  Colour ground_colour(int cx, int cy, Vec2 p) const;
  Colour ceiling_colour(Vec2 p) const;
  // Decals on one face (indices into decals()); empty for most faces.
  const std::vector<std::uint32_t>* decals_on(int cx, int cy, Side side) const;

 private:
  std::size_t index(int cx, int cy) const {
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(cx);
  }
  Rect bounds_;
  double cell_;
  int columns_ = 0, rows_ = 0;
  std::vector<std::uint16_t> materials_;
  std::vector<std::uint8_t> grounds_;
  std::vector<Material> material_table_;
  std::vector<Ground> ground_table_;
  std::vector<Decal> decals_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> face_decals_;
  bool first_ground_set_ = false;
};

}  // namespace seqtopo::simulator
