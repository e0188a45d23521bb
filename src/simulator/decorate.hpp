#pragma once
// Internal to seqtopo_sim: shared helpers for building scenario worlds.
#include <vector>

#include "seqtopo/simulator/random.hpp"
#include "seqtopo/simulator/world.hpp"

namespace seqtopo::simulator::detail {

// A maximal straight stretch of exposed wall faces: plane x = plane (west/east) or y = plane
// (south/north), covering u in [u0, u1].
struct FaceRun {
  Side side = Side::north;
  double plane = 0;
  double u0 = 0, u1 = 0;
};

// Exposed faces of solid cells at least `min_height` high whose free neighbour lies in `region`.
std::vector<FaceRun> face_runs(const GridWorld& world, Rect region, double min_height = 2.0);

// How densely, and with what, walls get decorated.
struct DecorStyle {
  bool outdoor = false;
  double spacing = 1.6;  // mean free wall between items [m]
  // Relative frequency of each item.
  double doors = 3, posters = 2, patches = 1.5, bars = 1, boards = 0.6, small = 0.5, windows = 0;
  std::vector<Colour> door_colours;
  std::vector<Colour> colours;  // posters and patches
};

DecorStyle office_style();
DecorStyle facade_style();

void decorate(GridWorld& world, Rect region, const DecorStyle& style, Rng& rng);
// One item of the given kind at [u, u + width] on a run; returns its width.
double place_item(GridWorld& world, const FaceRun& run, double u, int kind, const DecorStyle& style, Rng& rng,
                  double max_width);

}  // namespace seqtopo::simulator::detail
