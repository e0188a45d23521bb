// build_map_from_scores, the pipeline after the scores: on the scores build_map aligns it gives the same
// alignments, pruning and map, whether it reads them from the dense matrix or from a callable (the way
// streamed scores reach it).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::mapping {
namespace {

// Noise with a forward and a reverse revisit, symmetric, like a self-similarity matrix.
SimilarityMatrix revisit_matrix(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  SimilarityMatrix s(n, n, 0.0F);
  for (auto& v : s.values) v = noise(rng);
  for (std::size_t k = 0; k < 40; ++k) s(100 + k, 10 + k) += 3.0F, s(n - 1 - k, 40 + k) += 3.0F;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) s(j, i) = s(i, j);
  }
  return s;
}

// Odometry of a 45 m loop walked again and again (90 images per lap): the forward revisit 90 images back
// agrees with it, the reverse one does not, so the gate has something to drop.
std::vector<Pose2> straight_odometry(std::size_t n) {
  std::vector<Pose2> poses(n);
  for (std::size_t k = 0; k < n; ++k) poses[k] = {0.5 * static_cast<double>(k % 90), 0.0, 0.0};
  return poses;
}

void expect_same_map(const MapResult& a, const MapResult& b, const std::string& what) {
  EXPECT_EQ(a.alignments, b.alignments) << what;
  EXPECT_EQ(a.rejected, b.rejected) << what;
  EXPECT_EQ(a.pruning.kept, b.pruning.kept) << what;
  EXPECT_EQ(a.pruning.retained_count, b.pruning.retained_count) << what;
  EXPECT_EQ(a.pruning.pairs, b.pruning.pairs) << what;
  EXPECT_EQ(a.map.labels, b.map.labels) << what;
  ASSERT_EQ(a.map.places.size(), b.map.places.size()) << what;
  for (std::size_t p = 0; p < a.map.places.size(); ++p) {
    EXPECT_EQ(a.map.places[p].id, b.map.places[p].id) << what;
    EXPECT_EQ(a.map.places[p].images, b.map.places[p].images) << what;
  }
  EXPECT_EQ(a.map.edges, b.map.edges) << what;
  EXPECT_EQ(a.map.junctions, b.map.junctions) << what;
  ASSERT_EQ(a.map.segments.size(), b.map.segments.size()) << what;
  for (std::size_t k = 0; k < a.map.segments.size(); ++k)
    EXPECT_EQ(a.map.segments[k].places, b.map.segments[k].places) << what;
}

TEST(MapFromScores, EqualsBuildMapOnTheSameScores) {
  bool any_rejected = false;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const std::size_t n = 180 + 20 * seed;
    const SimilarityMatrix s = revisit_matrix(n, seed);
    for (const auto engine : {MapConfig::Engine::fast, MapConfig::Engine::exact}) {
      for (const bool with_odometry : {false, true}) {
        MapConfig config;
        config.engine = engine;
        // Keeps the default offset on these white-noise scores: alignment_scores below are the scores at it.
        config.phase.max_global_rate.reset();
        const auto odometry = with_odometry ? straight_odometry(n) : std::vector<Pose2>{};
        const MapResult dense = build_map(s, config, odometry);
        const SimilarityMatrix scores = alignment_scores({s}, config);
        ASSERT_EQ(dense.scores.values, scores.values);
        const std::string what = "seed " + std::to_string(seed) +
                                 (engine == MapConfig::Engine::fast ? " fast" : " exact") +
                                 (with_odometry ? " with odometry" : "");
        ASSERT_FALSE(dense.alignments.empty()) << what;
        any_rejected = any_rejected || !dense.rejected.empty();

        // The dense matrix as a source, and the same scores through a callable (as streamed scores arrive).
        const MapResult from_dense =
            build_map_from_scores(align::ScoreSource::dense(scores.values, n, n), config, odometry);
        const MapResult from_function = build_map_from_scores(
            align::ScoreSource::function(n, n, [&scores](std::size_t i, std::size_t j) { return scores(i, j); }),
            config, odometry);
        expect_same_map(dense, from_dense, what + ", dense source");
        expect_same_map(dense, from_function, what + ", function source");
        EXPECT_TRUE(from_dense.scores.empty());
      }
    }
  }
  EXPECT_TRUE(any_rejected);
}

TEST(MapFromScores, EveryFrameOfAHalfSpeedPassIsALoopClosure) {
  // Frames 300..379 drive 100..139 again at half speed: frame 300 + 2k and 301 + 2k both see frame 100 + k.
  // The scores are log-odds as they stand: a chance step costs 1 on average.
  const std::size_t n = 420;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(-1.0F, 1.0F);
  SimilarityMatrix s(n, n, 0.0F);
  for (auto& v : s.values) v = noise(rng);
  for (std::size_t i = 300; i < 380; ++i) s(i, 100 + (i - 300) / 2) += 4.0F;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) s(j, i) = s(i, j);
  }
  const MapResult r = build_map_from_scores(align::ScoreSource::dense(s.values, n, n), MapConfig{});
  std::vector<double> confidence(n, -1);
  for (const auto& p : r.pruning.pairs) {
    if (p.j + 2 >= 100 + (p.i - 300) / 2 && p.j <= 102 + (p.i - 300) / 2) {
      confidence[p.i] = std::max(confidence[p.i], p.confidence);
    }
  }
  std::size_t found = 0;
  for (std::size_t i = 302; i < 378; ++i) {
    found += confidence[i] > 0.05 ? 1 : 0;
  }
  // Gaps skip every other frame of the slow pass; those frames are loop closures of their own too.
  EXPECT_GE(found, 72U);
}

TEST(MapFromScores, RefusesBadSizes) {
  const SimilarityMatrix s = revisit_matrix(200, 9);
  EXPECT_THROW(build_map_from_scores(align::ScoreSource::dense(s.values, 100, 400)), std::invalid_argument);
  EXPECT_THROW(build_map_from_scores(align::ScoreSource::dense(std::span<const float>{}, 0, 0)), std::invalid_argument);
  const auto odometry = straight_odometry(199);
  EXPECT_THROW(build_map_from_scores(align::ScoreSource::dense(s.values, 200, 200), {}, odometry),
               std::invalid_argument);
}

// Settings out of range once ran (a negative frames per place asked for a vector larger than memory, a zero one
// divided by it): each is refused, naming its field.
TEST(MapFromScores, RefusesSettingsOutOfRangeNamingThem) {
  const SimilarityMatrix s = revisit_matrix(200, 9);
  const auto refused = [&](MapConfig c) -> std::string {
    try {
      build_map(s, c);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  MapConfig c;
  c.frames_per_place = -3.0;
  EXPECT_EQ(refused(c), "MapConfig.frames_per_place must be >= 1");
  c = {};
  c.significance.max_e_value = 0.0;
  EXPECT_EQ(refused(c), "MapConfig.significance.max_e_value must be > 0");
  c = {};
  c.significance.threshold = -1.0F;
  c.significance.max_e_value.reset();
  EXPECT_EQ(refused(c), "MapConfig.significance.threshold must be >= 0");
  c = {};
  c.search.cap = 0.0F;
  EXPECT_EQ(refused(c), "MapConfig.search.cap must be > 0");
  EXPECT_EQ(refused({}), "");
}

}  // namespace
}  // namespace seqtopo::mapping
