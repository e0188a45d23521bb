// Offline localization on synthetic query x map similarity matrices with planted correspondences
// (same direction, opposite direction, other speeds, gaps, query frames that are not in the map), and the
// building blocks against direct references.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "seqtopo/align/pair_posterior.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/localize/localize.hpp"

namespace seqtopo::localize {
namespace {

// Uniform noise in [0, 0.5); planted cells get 1.
SimilarityMatrix noise(std::size_t rows, std::size_t cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 0.5F);
  SimilarityMatrix s(rows, cols);
  for (auto& v : s.values) v = u(rng);
  return s;
}

std::size_t distance(std::size_t a, std::size_t b) { return a > b ? a - b : b - a; }

// Raw similarities in [0, 1]: an offset between noise and planted values, no enhancement needed.
LocalizeConfig plain_config() {
  LocalizeConfig c;
  c.enhance = false;
  c.score.contrast_offset = 0.6F;
  c.search.gap = 0.5F;
  c.significance.threshold = 3.0F;
  return c;
}

TEST(Localize, RecoversPlantedDiagonalAtAnotherSpeed) {
  // The query moves 1.5x as fast as the map was recorded: query q sees map frame round(1.5 q) + 7, so the
  // path skips map frames (gaps in the map) and is not a straight 45-degree diagonal.
  const std::size_t nq = 60, nm = 120;
  auto s = noise(nq, nm, 1);
  auto truth = [](std::size_t q) { return static_cast<std::size_t>(std::lround(1.5 * static_cast<double>(q))) + 7; };
  for (std::size_t q = 0; q < nq; ++q) s(q, truth(q)) = 1.0F;
  for (const auto& config : {plain_config(), LocalizeConfig{}}) {
    const auto r = localize_sequence(s, config);
    ASSERT_EQ(r.frames.size(), nq);
    for (std::size_t q = 0; q < nq; ++q) {
      // A local alignment may leave out an end frame whose step costs a gap; everything else is covered.
      if (q < 2 || q + 2 >= nq) {
        if (!r.frames[q].covered) continue;
      }
      ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
      EXPECT_LE(distance(r.frames[q].map, truth(q)), 1U) << q;
      EXPECT_EQ(r.frames[q].direction, align::Direction::forward);
    }
  }
}

TEST(Localize, RecoversSlowerQueryWithRepeatedMapFrames) {
  // The query moves at 0.6x: several query frames see the same map frame (gaps in the query).
  const std::size_t nq = 80, nm = 70;
  auto s = noise(nq, nm, 2);
  auto truth = [](std::size_t q) { return static_cast<std::size_t>(std::lround(0.6 * static_cast<double>(q))) + 10; };
  for (std::size_t q = 0; q < nq; ++q) s(q, truth(q)) = 1.0F;
  // Every repeated map frame costs a query gap, so the gap penalty must stay below what a matched frame gains.
  auto config = plain_config();
  config.search.gap = 0.2F;
  const auto r = localize_sequence(s, config);
  for (std::size_t q = 0; q < nq; ++q) {
    if ((q < 2 || q + 2 >= nq) && !r.frames[q].covered) continue;
    ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
    EXPECT_LE(distance(r.frames[q].map, truth(q)), 1U) << q;
  }
}

TEST(Localize, RecoversQueryDrivenTheOtherWay) {
  // An anti-diagonal: query q sees map frame 90 - q (the map traversed backwards).
  const std::size_t nq = 50, nm = 100;
  auto s = noise(nq, nm, 3);
  for (std::size_t q = 0; q < nq; ++q) s(q, 90 - q) = 1.0F;
  const auto r = localize_sequence(s, plain_config());
  for (std::size_t q = 0; q < nq; ++q) {
    ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
    EXPECT_EQ(r.frames[q].map, 90 - q) << q;
    EXPECT_EQ(r.frames[q].direction, align::Direction::reverse) << q;
  }
  auto no_reverse = plain_config();
  no_reverse.search.reverse = false;
  const auto f = localize_sequence(s, no_reverse);
  std::size_t right = 0;
  for (std::size_t q = 0; q < nq; ++q) right += f.frames[q].covered && f.frames[q].map == 90 - q ? 1 : 0;
  EXPECT_LT(right, nq / 4) << "without the reverse pass the backwards drive must not be found";
}

TEST(Localize, RecoversQueryDrivenTheOtherWayAtAnotherSpeed) {
  // Backwards at 1.4x: query q sees map frame 110 - round(1.4 q).
  const std::size_t nq = 60, nm = 120;
  auto s = noise(nq, nm, 15);
  auto truth = [](std::size_t q) { return 110 - static_cast<std::size_t>(std::lround(1.4 * static_cast<double>(q))); };
  for (std::size_t q = 0; q < nq; ++q) s(q, truth(q)) = 1.0F;
  const auto r = localize_sequence(s, LocalizeConfig{});
  for (std::size_t q = 0; q < nq; ++q) {
    if ((q < 2 || q + 2 >= nq) && !r.frames[q].covered) continue;
    ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
    EXPECT_LE(distance(r.frames[q].map, truth(q)), 1U) << q;
    EXPECT_EQ(r.frames[q].direction, align::Direction::reverse) << q;
  }
}

TEST(Localize, FramesOutsideTheMapAreNotCoveredAndJumpsAreFollowed) {
  // Query frames 0-29 follow map 10-39, frames 30-49 are somewhere new (noise only), frames 50-79 follow
  // map 100-129, then frames 80-99 again new.
  const std::size_t nq = 100, nm = 150;
  auto s = noise(nq, nm, 4);
  for (std::size_t q = 0; q < 30; ++q) s(q, q + 10) = 1.0F;
  for (std::size_t q = 50; q < 80; ++q) s(q, q + 50) = 1.0F;
  const auto r = localize_sequence(s, plain_config());
  for (std::size_t q = 0; q < nq; ++q) {
    const bool inside = q < 30 || (q >= 50 && q < 80);
    if (inside) {
      ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
      EXPECT_EQ(r.frames[q].map, q < 30 ? q + 10 : q + 50) << q;
    } else {
      // The ends of an alignment may run a frame or two into the noise, never far.
      const bool near_edge = (q >= 30 && q < 33) || (q >= 80 && q < 83) || (q >= 47 && q < 50);
      if (!near_edge) {
        EXPECT_FALSE(r.frames[q].covered) << q;
      }
    }
  }
}

TEST(Localize, BridgesAShortBadStretch) {
  // Ten query frames in the middle see nothing (e.g. a tunnel); the alignment carries the position through.
  const std::size_t nq = 80, nm = 100;
  auto s = noise(nq, nm, 5);
  for (std::size_t q = 0; q < nq; ++q) {
    if (q < 35 || q >= 40) s(q, q + 10) = 1.0F;
  }
  auto config = plain_config();
  config.score.contrast_offset =
      0.45F;  // noise costs less, so a few frames without evidence do not break the alignment
  const auto r = localize_sequence(s, config);
  for (std::size_t q = 0; q < nq; ++q) {
    ASSERT_TRUE(r.frames[q].covered) << q << " confidence " << r.frames[q].confidence << " E " << r.frames[q].e_value;
    EXPECT_LE(distance(r.frames[q].map, q + 10), 1U) << q;
  }
}

// Dark stretches at different places: query frames 40-59 are dark where the map was lit, and the map is dark at
// 120-139 where the query never goes; dark matches dark (0.95), the true cells of the dark query frames are poor.
// Unmasked, the dark query frames are placed in the map's dark stretch with confidence; with both stretches given
// as of little information, no frame is confidently wrong and the dark query frames are placed on the route around
// them.
TEST(Localize, DarkFramesAtDifferentPlacesAreNoEvidence) {
  const std::size_t nq = 100, nm = 200;
  auto s = noise(nq, nm, 11);
  const auto truth = [](std::size_t q) { return q + 10; };
  for (std::size_t q = 0; q < nq; ++q) s(q, truth(q)) = 1.0F;
  LowInformationFrames dark;
  for (std::size_t q = 40; q < 60; ++q) {
    dark.query.push_back(q);
    s(q, truth(q)) = 0.2F;
    for (std::size_t m = 120; m < 140; ++m) s(q, m) = 0.95F;
  }
  for (std::size_t m = 120; m < 140; ++m) dark.map.push_back(m);
  const auto config = plain_config();
  const std::vector<SimilarityMatrix> one{s};
  std::size_t confidently_wrong = 0;
  for (const auto& f : localize_sequence(one, config).frames) {
    confidently_wrong += f.confidence >= 0.5 && f.map >= 120 && f.map < 140 ? 1 : 0;
  }
  EXPECT_GE(confidently_wrong, 10U) << "unmasked, dark matches dark";
  const auto r = localize_sequence(one, config, dark);
  for (std::size_t q = 0; q < nq; ++q) {
    const auto& f = r.frames[q];
    if (f.confidence >= 0.5) {
      EXPECT_LE(distance(f.map, truth(q)), 1U) << q << " confidence " << f.confidence;
    }
    EXPECT_LE(distance(f.map, truth(q)), 2U) << q;
  }
  SimilarityMatrix masked = score_matrix(s, config);
  soft_mask(masked, dark);
  EXPECT_LE(masked(45, 125), 0.0F);
  EXPECT_EQ(masked(10, 20), score_matrix(s, config)(10, 20));
  EXPECT_THROW(soft_mask(masked, {{nq}, {}}), std::invalid_argument);
}

// A query that goes on along the route with nothing to see for its last 20 frames: their guesses carry on along
// the revisit (at their own low confidence, not in the map), up to the tolerance past the map's end (its last
// frame, the nearest), not further, where the robot has left the mapped route.
TEST(Localize, FramesWithoutEvidenceCarryOnAlongTheRoute) {
  const std::size_t nq = 60;
  for (const std::size_t nm : {100UL, 55UL}) {
    auto s = noise(nq, nm, 12);
    for (std::size_t q = 0; q < 40; ++q) s(q, q + 5) = 1.0F;
    for (const std::size_t tolerance : {0UL, 2UL}) {
      LocalizeConfig c = plain_config();
      c.tolerance = tolerance;
      const auto r = localize_sequence(s, c);
      for (std::size_t q = 44; q < nq; ++q) {
        const auto& f = r.frames[q];
        EXPECT_FALSE(f.covered) << q;
        EXPECT_LT(f.map, nm);
        if (q + 5 >= nm + tolerance) continue;  // further past the map's end its own guess stands (any noise cell)
        EXPECT_EQ(f.map, std::min(q + 5, nm - 1)) << q << " of a map of " << nm << ", tolerance " << tolerance;
        EXPECT_EQ(f.candidates.front(), f.map);
      }
    }
  }
}

TEST(Localize, EveryFrameTakesItsMostConfidentAlignmentsPosteriorGuessWithItsWindowedScore) {
  // Reference: per frame, the best over the alignments of P(revisit | E) x the row posterior (align::row_posteriors
  // called directly; between the alignment's first and last pair, over the row's posterior anywhere in the band),
  // and the local score of that alignment by brute force over its path.
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(-1.0F, 1.0F);
  for (int round = 0; round < 15; ++round) {
    SimilarityMatrix s(20 + rng() % 20, 20 + rng() % 20);
    for (auto& v : s.values) v = u(rng);
    LocalizeConfig c;
    c.enhance = false;
    c.score.contrast_offset = -0.2F;
    c.search.gap = 0.7F;
    c.significance.threshold = 1.0F;
    c.score_window = rng() % 4;
    const auto r = localize_sequence(s, c);
    const auto scores = score_matrix(s, c);
    ASSERT_EQ(r.e_values.size(), r.alignments.size());
    double lambda = r.statistics.valid() ? r.statistics.lambda : significance::ungapped_lambda(scores.values);
    if (!(lambda > 0)) lambda = 1.0;
    align::PosteriorConfig pc;
    pc.lambda = lambda;
    pc.gap_a = pc.gap_b = c.search.gap;
    pc.band = c.posterior_band;
    pc.tolerance = c.tolerance;
    // Per row, each alignment's account: its map frame, real x posterior, whether the row lies between its first
    // and last pair, and its weight P(revisit | E) exp(lambda x path score) (the path summed pair by pair here).
    struct Account {
      std::size_t col;
      double confidence;
      bool inside;
      double weight;
    };
    std::vector<std::vector<Account>> accounts(s.rows);
    for (std::size_t k = 0; k < r.alignments.size(); ++k) {
      const double e = r.e_values[k];
      const double real = std::isfinite(e) ? 1.0 / (1.0 + e / *c.significance.max_e_value)
                                           : (r.alignments[k].score >= c.significance.threshold ? 1.0 : 0.0);
      const auto source = align::ScoreSource::dense(scores.values, scores.rows, scores.cols);
      align::PosteriorConfig wide = pc;
      wide.tolerance = pc.band;
      const auto& a = r.alignments[k];
      double path = 0;
      for (std::size_t p = 0; p < a.pairs.size(); ++p) {
        path += scores(a.pairs[p].first, a.pairs[p].second);
        if (p > 0) {
          path -= c.search.gap * static_cast<double>(a.pairs[p].first - a.pairs[p - 1].first - 1 +
                                                     distance(a.pairs[p].second, a.pairs[p - 1].second) - 1);
        }
      }
      for (const auto& row : align::row_posteriors(a, source, pc)) {
        double posterior = row.posterior;
        const bool inside = row.row >= a.pairs.front().first && row.row <= a.pairs.back().first;
        if (inside) {
          // Anywhere in the band: the same row of the wide decoding.
          for (const auto& w : align::row_posteriors(a, source, wide)) {
            if (w.row == row.row && w.posterior > 0) posterior = std::min(1.0, row.posterior / w.posterior);
          }
        }
        accounts[row.row].push_back({row.col, real * posterior, inside, real * std::exp(lambda * path)});
      }
    }
    // The best account of each row, an account through the row shared with the others through it at places more
    // than the tolerance away.
    std::vector<double> best(s.rows, -1.0);
    for (std::size_t q = 0; q < s.rows; ++q) {
      double through = 0;
      for (const auto& x : accounts[q]) through += x.inside ? x.weight : 0.0;
      for (const auto& x : accounts[q]) {
        double share = 1;
        if (x.inside && through > 0) {
          double near = 0;
          for (const auto& y : accounts[q]) near += y.inside && distance(x.col, y.col) <= c.tolerance ? y.weight : 0.0;
          share = near / through;
        }
        best[q] = std::max(best[q], x.confidence * share);
      }
    }
    for (std::size_t q = 0; q < s.rows; ++q) {
      const auto& f = r.frames[q];
      ASSERT_FALSE(f.candidates.empty());
      EXPECT_EQ(f.candidates.front(), f.map);
      EXPECT_EQ(f.covered, f.confidence >= c.min_confidence) << q;
      if (best[q] < 0) {
        EXPECT_EQ(f.alignment, FrameMatch::npos) << q;
        EXPECT_EQ(f.confidence, 0.0);
        continue;
      }
      EXPECT_NEAR(f.confidence, best[q], 1e-12) << round << " frame " << q;
      ASSERT_LT(f.alignment, r.alignments.size());
      // The local score of the alignment that gave the guess.
      const auto& a = r.alignments[f.alignment];
      double local = 0;
      bool started = false;
      std::size_t pi = 0, pj = 0;
      for (const auto& [i, j] : a.pairs) {
        if (distance(i, q) > c.score_window) continue;
        local += scores(i, j);
        if (started) local -= c.search.gap * static_cast<double>((i - pi - 1) + distance(j, pj) - 1);
        started = true;
        pi = i;
        pj = j;
      }
      EXPECT_NEAR(f.score, local, 1e-3) << round << " frame " << q;
    }
  }
}

TEST(Localize, ScoreRowIsTheWindowedZScoreMinusOffset) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0F, 3.0F);
  SimilarityMatrix s(3, 37);
  for (auto& v : s.values) v = u(rng);
  for (std::size_t window : {0U, 1U, 5U, 100U}) {
    LocalizeConfig c;
    c.score.contrast_window = window;
    c.score.contrast_offset = 0.25F;
    const auto out = score_matrix(s, c);
    for (std::size_t i = 0; i < s.rows; ++i) {
      for (std::size_t j = 0; j < s.cols; ++j) {
        const std::size_t w = window == 0 ? s.cols : window;
        double sum = 0, n = 0;
        for (std::size_t k = 0; k < s.cols; ++k) {
          if (distance(k, j) <= w) {
            sum += s(i, k);
            n += 1;
          }
        }
        const double mean = sum / n;
        double var = 0;
        for (std::size_t k = 0; k < s.cols; ++k) {
          if (distance(k, j) <= w) var += (s(i, k) - mean) * (s(i, k) - mean);
        }
        const double expected = (s(i, j) - mean) / std::sqrt(var / n) - 0.25;
        EXPECT_NEAR(out(i, j), expected, 1e-3) << i << " " << j << " window " << window;
      }
    }
  }
}

TEST(Localize, SingleFrameIsTheRowMaximum) {
  auto s = noise(30, 40, 8);
  s(3, 7) = s(3, 9) = 2.0F;  // a tie goes to the smaller index
  const auto f = single_frame_matches(s, 3);
  for (std::size_t q = 0; q < s.rows; ++q) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < s.cols; ++j) {
      if (s(q, j) > s(q, best)) best = j;
    }
    EXPECT_EQ(f[q].map, best);
    EXPECT_EQ(f[q].score, s(q, best));
    ASSERT_EQ(f[q].candidates.size(), 3U);
    EXPECT_GE(s(q, f[q].candidates[1]), s(q, f[q].candidates[2]));
  }
  EXPECT_EQ(f[3].map, 7U);
  EXPECT_EQ(f[3].candidates[1], 9U);
}

TEST(Localize, DoesNotDependOnThreads) {
  auto s = noise(60, 60, 9);
  for (std::size_t q = 0; q < 40; ++q) s(q, q + 5) = 1.0F;
  for (std::size_t q = 0; q < 30; ++q) s(q + 30, 50 - q) = 1.0F;
  auto c = plain_config();
  c.threads = 1;
  const auto one = localize_sequence(s, c);
  c.threads = 2;
  const auto two = localize_sequence(s, c);
  EXPECT_EQ(one.alignments, two.alignments);
  for (std::size_t q = 0; q < s.rows; ++q) {
    EXPECT_EQ(one.frames[q].map, two.frames[q].map);
    EXPECT_EQ(one.frames[q].score, two.frames[q].score);
  }
}

TEST(Localize, RejectsBadInput) {
  const auto s = noise(5, 5, 10);
  EXPECT_THROW(localize_sequence(SimilarityMatrix{}), std::invalid_argument);
  auto nan = s;
  nan(2, 2) = std::nanf("");
  EXPECT_THROW(localize_sequence(nan), std::invalid_argument);
  EXPECT_THROW(single_frame_matches(nan), std::invalid_argument);
  LocalizeConfig c;
  c.search.gap = -1.0F;
  EXPECT_THROW(localize_sequence(s, c), std::invalid_argument);
  c = {};
  c.search.cap = 0.0F;
  EXPECT_THROW(localize_sequence(s, c), std::invalid_argument);
  c = {};
  c.significance.threshold = std::nanf("");
  EXPECT_THROW(localize_sequence(s, c), std::invalid_argument);
  c = {};
  c.candidates = 0;
  EXPECT_THROW(localize_sequence(s, c), std::invalid_argument);
  EXPECT_THROW(single_frame_matches(s, 0), std::invalid_argument);
}

TEST(Localize, NothingToFindIsANormalResult) {
  SimilarityMatrix s(10, 12, 0.0F);  // flat: every cell scores -offset
  const auto r = localize_sequence(s);
  EXPECT_TRUE(r.alignments.empty());
  for (const auto& f : r.frames) EXPECT_FALSE(f.covered);
}

}  // namespace
}  // namespace seqtopo::localize
