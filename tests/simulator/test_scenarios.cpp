// Every scenario renders and its ground truth is consistent; runs are deterministic by seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "seqtopo/simulator/scenarios.hpp"

namespace seqtopo::simulator {
namespace {

SimulationConfig tiny() {
  SimulationConfig c;
  c.panorama.width = 36;
  c.panorama.height = 6;
  c.panorama.supersample = 1;
  c.forward_images = false;
  return c;
}

class SequenceScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(SequenceScenario, RendersWithConsistentGroundTruth) {
  const SimulationConfig config = tiny();
  const ScenarioSetup setup = build_scenario(GetParam(), config);
  const SimulatedRun run = simulate(setup, config);
  const std::size_t n = run.poses.size();
  ASSERT_GT(n, 100U);
  EXPECT_EQ(run.odometry.size(), n);
  EXPECT_EQ(run.places.size(), n);
  EXPECT_EQ(run.on_path.size(), n);
  ASSERT_EQ(run.panoramas.size(), n);
  EXPECT_EQ(run.panoramas.front().width, 36);
  EXPECT_TRUE(run.images.empty());
  EXPECT_GT(run.floor_plan.width, 100);

  // Place ids are numbered in order of first visit, and a place is a short stretch of path.
  int next = 0;
  std::map<int, std::vector<std::size_t>> members;
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_LE(run.places[k], next);
    if (run.places[k] == next) ++next;
    members[run.places[k]].push_back(k);
  }
  const double longest = 2 * std::max(config.places.place_length, 2 * config.places.junction_radius);
  for (const auto& [place, frames] : members) {
    for (std::size_t a : frames) {
      for (std::size_t b : frames) {
        ASSERT_LE(distance(run.on_path[a], run.on_path[b]), longest) << "place " << place;
      }
    }
  }
  // The robot stays within a metre of its path and frames are one interval of travel apart.
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_LE(distance({run.poses[k].x, run.poses[k].y}, run.on_path[k]), 1.0);
    if (k > 0) {
      EXPECT_LE(std::hypot(run.poses[k].x - run.poses[k - 1].x, run.poses[k].y - run.poses[k - 1].y),
                run.interval + 1e-9);
    }
  }
  for (int j : run.junctions) EXPECT_LT(j, next);
  EXPECT_EQ(run.odometry.front(), run.poses.front());

  // The same-place matrix is symmetric, empty near the diagonal, and agrees with the places on clear cases.
  const std::size_t band = 10;
  const auto truth = same_place_matrix(run, 1.0, band);
  ASSERT_EQ(truth.rows, n);
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      ASSERT_EQ(truth(i, j), truth(j, i));
      if ((i > j ? i - j : j - i) < band) {
        ASSERT_EQ(truth(i, j), 0);
      }
      if (truth(i, j) != 0) ++pairs;
      // Frames on exactly the same path point are the same place.
      if (i != j && (i > j ? i - j : j - i) >= band && distance(run.on_path[i], run.on_path[j]) < 1e-6) {
        ASSERT_EQ(run.places[i], run.places[j]);
        ASSERT_EQ(truth(i, j), 255);
      }
    }
  }
  if (GetParam() == "aliasing") {
    EXPECT_EQ(pairs, 0U);  // identical-looking corridors, but no revisit
  } else {
    EXPECT_GT(pairs, 2 * n / 5);  // a large part of every other route is a revisit
  }
}

INSTANTIATE_TEST_SUITE_P(All, SequenceScenario,
                         ::testing::Values("figure-eight", "corridor-reverse", "nested-loops", "zigzag", "aliasing"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(Scenarios, JunctionsAreTheBranchingPointsOfTheRoute) {
  const std::map<std::string, std::size_t> expected{
      {"figure-eight", 2}, {"corridor-reverse", 1}, {"nested-loops", 4}, {"zigzag", 2}, {"aliasing", 0}};
  SimulationConfig config = tiny();
  config.panorama.width = 8;
  config.panorama.height = 2;
  for (const auto& [name, count] : expected) {
    EXPECT_EQ(simulate(name, config).junctions.size(), count) << name;
  }
}

TEST(Scenarios, ZigZagTraversalRecordsMoreFramesThanTheStraightOne) {
  SimulationConfig config = tiny();
  config.panorama.width = 8;
  config.panorama.height = 2;
  const SimulatedRun run = simulate("zigzag", config);
  // The third leg zig-zags along a stretch the first two legs drove straight.
  std::map<int, std::size_t> per_leg;
  for (int t : run.traversals) ++per_leg[t];
  ASSERT_EQ(per_leg.size(), 3U);
  double offset = 0;
  for (std::size_t k = 0; k < run.poses.size(); ++k) {
    if (run.traversals[k] == 2) offset = std::max(offset, distance({run.poses[k].x, run.poses[k].y}, run.on_path[k]));
  }
  EXPECT_GT(offset, 0.5);
  // 160 m of path at 0.5 m would be 320 frames; the zig-zag adds about a quarter.
  EXPECT_GT(per_leg[2], 380U);
  SimulationConfig straight = config;
  straight.zigzag_amplitude = 0.0;
  EXPECT_LT(simulate("zigzag", straight).poses.size(), run.poses.size());
}

TEST(Scenarios, CorridorReverseRevisitsTheCorridorBackwards) {
  SimulationConfig config = tiny();
  config.panorama.width = 8;
  config.panorama.height = 2;
  const SimulatedRun run = simulate("corridor-reverse", config);
  // Every frame on the way out has a frame on the way back within half an interval of its path point;
  // nearly all share its place (the rest straddle a place boundary), and the robot faces the other way
  // on the same line.
  const std::size_t n = run.poses.size();
  std::size_t matched = 0, same_place = 0;
  for (std::size_t i = 0; i < n / 3; ++i) {
    if (run.on_path[i].x < 1 || run.on_path[i].x > 33) continue;  // away from the corridor ends
    std::size_t best = n;
    double best_d = 1e9;
    for (std::size_t j = 2 * n / 3; j < n; ++j) {
      const double d = distance(run.on_path[i], run.on_path[j]);
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    ASSERT_LT(best_d, run.interval / 2 + 1e-9) << i;
    ++matched;
    if (run.places[i] == run.places[best]) ++same_place;
    if (run.on_path[i].x > 2 && run.on_path[i].x < 33) {  // away from the ends of the corridor
      EXPECT_NEAR(std::abs(wrap_angle(run.poses[i].theta - run.poses[best].theta)), std::numbers::pi, 1e-6);
      EXPECT_NEAR(run.poses[i].y, run.poses[best].y, 1e-6);
    }
  }
  EXPECT_GT(matched, 100U);
  EXPECT_GT(same_place, matched * 8 / 10);
}

struct SurveyCase {
  std::string name;
  std::size_t map, test, adjacent_per_test_min;
};

TEST(Scenarios, SurveysHaveTheirPapersPointCountsAndAdjacency) {
  const SurveyCase cases[] = {{"rooms", 10, 30, 1}, {"ground-floor", 21, 22, 2}, {"white-hall", 15, 18, 2}};
  for (const auto& c : cases) {
    SimulationConfig config = tiny();
    const SimulatedRun run = simulate(c.name, config);
    EXPECT_EQ(run.kind, ScenarioKind::survey);
    const auto maps = std::count_if(run.points.begin(), run.points.end(), [](const SurveyPoint& p) { return p.map; });
    EXPECT_EQ(static_cast<std::size_t>(maps), c.map) << c.name;
    EXPECT_EQ(run.points.size() - static_cast<std::size_t>(maps), c.test) << c.name;
    ASSERT_EQ(run.panoramas.size(), run.points.size());
    std::set<std::string> ids;
    for (const auto& p : run.points) ids.insert(p.id);
    EXPECT_EQ(ids.size(), run.points.size()) << c.name;
    std::map<int, std::size_t> adjacent;
    for (const auto& [t, m] : run.adjacency) {
      ASSERT_FALSE(run.points[static_cast<std::size_t>(t)].map);
      ASSERT_TRUE(run.points[static_cast<std::size_t>(m)].map);
      ++adjacent[t];
      // Adjacent map points are close by (rooms: the same room; floors: a neighbour on the map graph).
      const Pose2& a = run.points[static_cast<std::size_t>(t)].pose;
      const Pose2& b = run.points[static_cast<std::size_t>(m)].pose;
      EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 4.0) << c.name;
    }
    EXPECT_EQ(adjacent.size(), c.test) << c.name;
    for (const auto& [t, count] : adjacent) EXPECT_GE(count, c.adjacent_per_test_min) << c.name;
    // A test point's place is its nearest map point, which is among its adjacent ones.
    for (std::size_t t = 0; t < run.points.size(); ++t) {
      const auto& p = run.points[t];
      if (p.map) continue;
      bool nearest_is_adjacent = false;
      for (const auto& [tt, m] : run.adjacency) {
        if (static_cast<std::size_t>(tt) == t && run.points[static_cast<std::size_t>(m)].place == p.place)
          nearest_is_adjacent = true;
      }
      EXPECT_TRUE(nearest_is_adjacent) << c.name << " " << p.id;
    }
  }
}

TEST(Determinism, SameSeedSameBytesWhateverTheThreadCount) {
  SimulationConfig config;
  config.panorama.width = 90;
  config.panorama.height = 15;
  config.camera.width = 40;
  config.camera.height = 30;
  config.max_frames = 24;
  config.threads = 1;
  const SimulatedRun a = simulate("figure-eight", config);
  config.threads = 3;
  const SimulatedRun b = simulate("figure-eight", config);
  ASSERT_EQ(a.panoramas.size(), 24U);
  ASSERT_EQ(a.images.size(), 24U);
  for (std::size_t k = 0; k < a.panoramas.size(); ++k) {
    EXPECT_EQ(a.panoramas[k].pixels, b.panoramas[k].pixels) << k;
    EXPECT_EQ(a.images[k].pixels, b.images[k].pixels) << k;
  }
  EXPECT_EQ(a.odometry, b.odometry);
  EXPECT_EQ(a.places, b.places);
  EXPECT_EQ(a.floor_plan.pixels, b.floor_plan.pixels);

  config.seed = 2;
  const SimulatedRun c = simulate("figure-eight", config);
  EXPECT_NE(a.panoramas[5].pixels, c.panoramas[5].pixels);
  EXPECT_NE(a.odometry, c.odometry);
  EXPECT_EQ(a.poses, c.poses);  // the route does not depend on the seed
}

TEST(Scenarios, LightingChangesBetweenTraversalsUnlessTurnedOff) {
  SimulationConfig config;
  const ScenarioSetup lit = build_scenario("nested-loops", config);
  ASSERT_EQ(lit.legs.size(), 3U);
  EXPECT_EQ(lit.legs[0].lighting.gain, 1.0);
  EXPECT_NE(lit.legs[1].lighting.gain, 1.0);
  config.lighting_change = 0;
  for (const auto& leg : build_scenario("nested-loops", config).legs) {
    EXPECT_EQ(leg.lighting.gain, 1.0);
    EXPECT_EQ(leg.lighting.tint, (std::array<double, 3>{1.0, 1.0, 1.0}));
  }
  for (const auto& light : build_scenario("rooms", config).point_lighting) EXPECT_EQ(light.gain, 1.0);
}

TEST(Scenarios, UnknownNamesAndBadSettingsAreRejected) {
  EXPECT_THROW(build_scenario("no-such-world"), std::invalid_argument);
  SimulationConfig config = tiny();
  config.interval = -1.0;
  EXPECT_THROW(simulate("figure-eight", config), std::invalid_argument);
  config = tiny();
  config.panorama.width = 0;
  EXPECT_THROW(simulate("figure-eight", config), std::invalid_argument);
  for (const auto& s : scenarios()) EXPECT_NO_THROW(build_scenario(s.name)) << s.name;
}

}  // namespace
}  // namespace seqtopo::simulator
