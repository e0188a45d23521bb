// The map pipeline's structured progress (pipeline/progress.hpp): every stage begun and ended in order, and the
// alignment stage counting the cells its passes read, so that the command line can show a bar with an ETA there as
// in the similarity stage (it showed a spinner).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "seqtopo/pipeline/map_pipeline.hpp"

namespace seqtopo::pipeline {
namespace {

// A route of n frames driven twice: S[i][j] high where j is i's frame on the other drive, noise elsewhere.
SimilarityMatrix two_drives(std::size_t n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> noise(0.0F, 0.6F);
  SimilarityMatrix s(n, n, 0.0F);
  const std::size_t half = n / 2;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      const bool same = i == j || (i >= half && i - half == j);
      s(i, j) = s(j, i) = same ? 1.0F : noise(rng);
    }
  }
  return s;
}

struct Recorded {
  std::vector<StageEvent::Kind> kinds;
  std::vector<std::string> names, units;
  std::vector<std::size_t> done, total;
};

Recorded run_with_threads(unsigned threads, bool reverse, std::vector<SimilarityMatrix> matrices = {}) {
  MapSettings settings;
  settings.map.threads = threads;
  settings.map.search.reverse = reverse;
  Recorded r;
  MapObserver observer;
  observer.stage = [&r](const StageEvent& e) {
    r.kinds.push_back(e.kind);
    r.names.emplace_back(e.name);
    r.units.emplace_back(e.unit);
    r.done.push_back(e.done);
    r.total.push_back(e.total);
  };
  if (matrices.empty()) matrices.push_back(two_drives(400));
  map_similarities(std::move(matrices), {}, settings, {}, {}, observer);
  return r;
}

TEST(StageProgress, TheAlignmentCountsTheCellsItsPassesRead) {
  for (const unsigned threads : {1U, 2U}) {
    for (const bool reverse : {false, true}) {
      const Recorded r = run_with_threads(threads, reverse);
      // The cells below the diagonal at least min_separation (10 frames) from it, in each pass.
      const std::size_t total = (reverse ? 2 : 1) * (400 - 10) * (400 - 10 + 1) / 2;
      std::size_t advances = 0, last = 0, at_total = 0;
      for (std::size_t k = 0; k < r.kinds.size(); ++k) {
        if (r.kinds[k] != StageEvent::Kind::advance || r.units[k] != "cells aligned") continue;
        ++advances;
        EXPECT_EQ(r.names[k], "alignments, pruning, labels, topology");
        EXPECT_EQ(r.total[k], total);
        EXPECT_LE(r.done[k], total);
        if (r.done[k] == total) ++at_total;
        if (threads == 1) {
          EXPECT_GT(r.done[k], last) << "one pass at a time: never backwards";
        }
        last = r.done[k];
      }
      EXPECT_GE(advances, (reverse ? 2U : 1U) * 250U) << threads << " threads, reverse " << reverse;
      EXPECT_EQ(last, total) << "the last event tells the whole, once the alignment has ended";
      EXPECT_EQ(at_total, 1U) << "the reads never tell the whole themselves";
      // Every stage begun is ended before the next begins.
      int open = 0;
      for (const auto kind : r.kinds) {
        if (kind == StageEvent::Kind::begin) {
          EXPECT_EQ(open++, 0);
        }
        if (kind == StageEvent::Kind::end) {
          EXPECT_EQ(--open, 0);
        }
      }
    }
  }
}

// Before its cells, the alignment stage counts its other steps, each in its own unit and each to its whole, in the
// order they run: the blind check's maps of each descriptor alone, the contrast enhancement of the similarities
// fused, the statistics' fits (one per offset tried).
TEST(StageProgress, EveryStepOfTheAlignmentStageCountsToItsWhole) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.0F, 1.0F);
  SimilarityMatrix blind(400, 400, 0.0F);
  for (std::size_t i = 0; i < 400; ++i) {
    for (std::size_t j = 0; j <= i; ++j) blind(i, j) = blind(j, i) = i == j ? 1.0F : noise(rng);
  }
  const Recorded r = run_with_threads(1, true, {two_drives(400), blind});
  std::vector<std::string> order;                         // the units in the order they first appear
  std::vector<std::pair<std::size_t, std::size_t>> last;  // each unit's last (done, total)
  for (std::size_t k = 0; k < r.kinds.size(); ++k) {
    if (r.kinds[k] != StageEvent::Kind::advance) continue;
    if (order.empty() || order.back() != r.units[k]) {
      ASSERT_EQ(std::count(order.begin(), order.end(), r.units[k]), 0) << r.units[k] << " told again after another";
      order.push_back(r.units[k]);
      last.emplace_back();
    }
    EXPECT_LE(r.done[k], r.total[k]) << r.units[k];
    EXPECT_GE(r.done[k], last.back().first) << r.units[k] << ": never backwards";
    last.back() = {r.done[k], r.total[k]};
  }
  const std::vector<std::string> expected{"descriptors mapped alone", "similarities enhanced", "statistics' fits",
                                          "cells aligned"};
  EXPECT_EQ(order, expected);
  ASSERT_EQ(last.size(), expected.size());
  EXPECT_EQ(last[0], std::make_pair(std::size_t{2}, std::size_t{2}));
  EXPECT_EQ(last[1].first, last[1].second);  // both similarities, or the one left when the blind is out
  EXPECT_GE(last[2].second, 1U);
  EXPECT_EQ(last[2].first, last[2].second);
  EXPECT_EQ(last[3].first, last[3].second);
}

}  // namespace
}  // namespace seqtopo::pipeline
