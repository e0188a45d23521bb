#pragma once
// Named synthetic worlds that reproduce the two papers' experiments, with exact ground truth.
//
//   SimulationConfig config;  config.seed = 7;
//   SimulatedRun run = simulate("figure-eight", config);
//   // run.panoramas[k], run.poses[k], run.odometry[k], run.places[k] ...
//
// Mapping scenarios record a sequence of frames along a route; localization scenarios (rooms,
// ground-floor, white-hall) record one panorama per map or test point instead.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/simulator/robot.hpp"
#include "seqtopo/simulator/world.hpp"

namespace seqtopo::simulator {

enum class ScenarioKind { sequence, survey };

struct ScenarioInfo {
  std::string name;
  ScenarioKind kind = ScenarioKind::sequence;
  std::string description;
};

const std::vector<ScenarioInfo>& scenarios();

struct SimulationConfig {
  std::uint64_t seed = 1;
  std::optional<double> interval;          // [m] between frames; default per scenario (0.25 indoors, 0.5 outdoors)
  double odometry_noise = 1.0;             // multiplies the scenario's odometry error model (0 = exact odometry)
  std::optional<double> heading_drift;     // [rad/m], overrides the scenario's
  std::optional<double> scale_error;       // overrides the scenario's
  std::optional<double> zigzag_amplitude;  // [m], overrides the zig-zag traversal's
  PanoramaCamera panorama;
  PinholeCamera camera;
  bool forward_images = true;
  double pixel_noise = 2.0;      // [grey levels]
  double lighting_change = 1.0;  // scales the lighting differences between traversals (0 = identical lighting)
  PlaceConfig places;
  std::size_t max_frames = 0;  // keep only the first N frames (0 = all)
  int threads = 0;             // 0 = OpenMP default
};

// A point of a localization survey (the second paper's map and test points).
struct SurveyPoint {
  std::string id;
  bool map = true;  // map point (database) or test point (query)
  Pose2 pose;
  int place = 0;  // the map point's index for map points; the nearest map point's for test points
};

// The world, paths and route of a scenario, before anything is rendered.
struct ScenarioSetup {
  std::string name;
  ScenarioKind kind = ScenarioKind::sequence;
  GridWorld world{Rect{0, 0, 1, 1}, 0.25};
  PathGraph graph;
  std::vector<RouteLeg> legs;
  double interval = 0.25;
  OdometryNoise odometry;
  std::vector<SurveyPoint> points;
  std::vector<Lighting> point_lighting;        // one per point
  std::vector<std::pair<int, int>> adjacency;  // (test point, adjacent map point), indices into points
};

struct SimulatedRun {
  std::string scenario;
  ScenarioKind kind = ScenarioKind::sequence;
  double interval = 0.0;  // [m]
  // Sequence scenarios, one entry per frame:
  std::vector<Pose2> poses;      // ground truth
  std::vector<Pose2> odometry;   // cumulative, drifting
  std::vector<Vec2> on_path;     // the path point being followed [m]
  std::vector<int> places;       // ground-truth place id (0.. in order of first visit)
  std::vector<int> traversals;   // route leg of each frame
  std::vector<int> junctions;    // place ids that are branching/merging points of the route
  std::vector<RgbImage> images;  // forward camera (empty when disabled)
  // Both kinds: panoramas (per frame, or per survey point).
  std::vector<RgbImage> panoramas;
  // Survey scenarios:
  std::vector<SurveyPoint> points;
  std::vector<std::pair<int, int>> adjacency;
  RgbImage floor_plan;
};

// Throws std::invalid_argument for an unknown name.
ScenarioSetup build_scenario(const std::string& name, const SimulationConfig& config = {});
SimulatedRun simulate(const ScenarioSetup& setup, const SimulationConfig& config = {});
inline SimulatedRun simulate(const std::string& name, const SimulationConfig& config = {}) {
  return simulate(build_scenario(name, config), config);
}

// Ground-truth same-place matrix (N x N, 255/0): frames i and j show the same place when their path points
// are within `radius` [m] of each other; pairs with |i - j| < band are zero so that consecutive frames do
// not count as loop closures.
DenseMatrix<std::uint8_t> same_place_matrix(const SimulatedRun& run, double radius, std::size_t band);

// Top view: walls and their decals in colour, the route (red, start green, end blue), junctions
// (circles) and survey points (map blue, test orange, adjacency grey).
RgbImage draw_floor_plan(const ScenarioSetup& setup, const SimulatedRun& run, double pixels_per_metre = 12.0);

}  // namespace seqtopo::simulator
