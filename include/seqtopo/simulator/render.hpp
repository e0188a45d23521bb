#pragma once
// Ray-cast cameras over a GridWorld: a panoramic cylinder (the mapping paper's mirror camera) and a
// forward pinhole camera. Each image depends only on its inputs and noise seed, so frames can be
// rendered in any order on any number of threads with identical results.
#include <array>
#include <cstdint>
#include <numbers>

#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/simulator/geometry.hpp"
#include "seqtopo/simulator/world.hpp"

namespace seqtopo::simulator {

// 360 degrees across the width: column 0 looks along the robot heading, angles increase
// counter-clockwise (column c is centred on heading + 2*pi*c/width). Rows are linear in elevation,
// row 0 at the top.
struct PanoramaCamera {
  int width = 360;
  int height = 60;
  double elevation_min = -30.0 * std::numbers::pi / 180.0;  // [rad], bottom edge
  double elevation_max = 30.0 * std::numbers::pi / 180.0;   // [rad], top edge
  double mount_height = 1.5;                                // [m] above the floor (the paper's mast)
  int supersample = 2;                                      // rays per pixel along each axis
};

struct PinholeCamera {
  int width = 160;
  int height = 120;
  double horizontal_fov = 60.0 * std::numbers::pi / 180.0;  // [rad]
  double mount_height = 1.0;                                // [m]
  int supersample = 2;
};

// Illumination of one traversal: global gain, per-channel tint and sensor noise.
struct Lighting {
  double gain = 1.0;
  std::array<double, 3> tint{1.0, 1.0, 1.0};
  double noise_sigma = 2.0;  // [grey levels], Gaussian per pixel and channel
};

RgbImage render_panorama(const GridWorld& world, const Pose2& pose, const PanoramaCamera& camera,
                         const Lighting& lighting = {}, std::uint64_t noise_seed = 0);
RgbImage render_pinhole(const GridWorld& world, const Pose2& pose, const PinholeCamera& camera,
                        const Lighting& lighting = {}, std::uint64_t noise_seed = 0);

}  // namespace seqtopo::simulator
