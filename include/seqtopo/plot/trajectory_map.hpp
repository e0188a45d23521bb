#pragma once
// The metric picture of a topological map in the style of the mapping paper's Figs. 4-6: panels side by
// side, e.g. (a) cumulative odometry and (b) the corrected map, optionally (c) ground truth. Each panel
// draws the path as a line, the image positions as dots coloured by place, and the loop-closure pairs as
// thin lines, on axes with metre ticks. Each panel has its own scale (equal in x and y), since drifting
// odometry can cover a much larger area than the corrected map.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::plot {

struct TrajectoryPanel {
  std::string title;         // e.g. "(a) Cumulative odometry"
  std::vector<Pose2> poses;  // one per image [m, m, rad]
};

struct TrajectoryMapConfig {
  int panel_width = 640;   // [pixels]
  int panel_height = 640;  // [pixels]
  int dot_radius = 3;      // [pixels]
};

// Colour of a revisited place's dots (a place seen in two or more images). Places seen once and negative
// labels are drawn in kSingleVisitColour, so the revisits stand out.
std::array<std::uint8_t, 3> place_colour(int label);
inline constexpr std::array<std::uint8_t, 3> kSingleVisitColour{150, 150, 150};

// Returns an image of panels.size() * panel_width by panel_height pixels. labels may be empty (all dots in
// one colour); otherwise it has one entry per pose of every panel. Throws std::invalid_argument when
// there is no panel, a size does not match, a loop pair is out of range or a pose is not finite.
RgbImage trajectory_map_image(const std::vector<TrajectoryPanel>& panels, const std::vector<int>& labels,
                              const std::vector<std::pair<std::size_t, std::size_t>>& loop_pairs,
                              const TrajectoryMapConfig& config = {});

}  // namespace seqtopo::plot
