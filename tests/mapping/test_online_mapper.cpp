// The online mapper against independent references: a textbook full-table fill of the self search (and the
// alignment engine's best score), the offline engine's alignments on planted revisits (forward, reverse, three
// traversals), the distance functions, and its own event rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>

#include "common/sanitizers.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/mapping/online_mapper.hpp"
#include "seqtopo/significance/score_statistics.hpp"
#include "seqtopo/similarity/distance.hpp"

namespace seqtopo::mapping {
namespace {

using align::Direction;

// Full tables of the self search in original coordinates: cells (r, c) with r - c >= sep, 0 elsewhere;
// forward from (r-1, c-1) and (r, c-1), reverse from (r-1, c+1) and (r, c+1), as align/smith_waterman.hpp states.
std::vector<std::vector<float>> naive_self_table(const SimilarityMatrix& s, std::size_t sep, bool reverse, float gap,
                                                 std::optional<float> cap) {
  const std::size_t n = s.rows;
  std::vector<std::vector<float>> h(n, std::vector<float>(n, 0.0F));
  auto at = [&](long r, long c) -> float {
    if (r < 0 || c < 0 || c >= static_cast<long>(n)) return 0.0F;
    if (r - c < static_cast<long>(sep)) return 0.0F;
    return h[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  };
  for (long r = 0; r < static_cast<long>(n); ++r) {
    for (long k = 0; k < static_cast<long>(n); ++k) {
      const long c = reverse ? static_cast<long>(n) - 1 - k : k;
      if (r - c < static_cast<long>(sep)) continue;
      const float diag = reverse ? at(r - 1, c + 1) : at(r - 1, c - 1);
      const float side = reverse ? at(r, c + 1) : at(r, c - 1);
      float v = std::max(0.0F, diag + s(static_cast<std::size_t>(r), static_cast<std::size_t>(c)));
      v = std::max(v, at(r - 1, c) - gap);
      v = std::max(v, side - gap);
      if (cap) v = std::min(v, *cap);
      h[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = v;
    }
  }
  return h;
}

std::vector<float> score_row(const SimilarityMatrix& s, std::size_t t, std::size_t sep) {
  const std::size_t n = t >= sep ? t - sep + 1 : 0;
  return {s.values.begin() + static_cast<std::ptrdiff_t>(t * s.cols),
          s.values.begin() + static_cast<std::ptrdiff_t>(t * s.cols + n)};
}

TEST(OnlineMapper, RowsEqualTheTextbookFillAndTheEnginesBest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0F, 0.6F);
  for (int round = 0; round < 12; ++round) {
    const std::size_t n = 20 + rng() % 40, sep = 1 + rng() % 6;
    SimilarityMatrix s(n, n);
    for (auto& v : s.values) v = u(rng);
    OnlineMapConfig c;
    c.search.min_separation = sep;
    c.search.gap = 0.2F + 0.1F * static_cast<float>(rng() % 8);
    c.search.cap = round % 3 == 0 ? std::optional<float>{} : std::optional<float>{1.5F + static_cast<float>(rng() % 4)};
    c.significance.threshold = c.search.cap ? std::min(*c.search.cap, 1.0F) : 1.0F;
    c.significance.max_e_value.reset();
    const auto fwd = naive_self_table(s, sep, false, c.search.gap, c.search.cap);
    const auto rev = naive_self_table(s, sep, true, c.search.gap, c.search.cap);
    OnlineMapper m(c);
    float online_best_fwd = 0, online_best_rev = 0;
    for (std::size_t t = 0; t < n; ++t) {
      m.add_scores(score_row(s, t, sep));
      const auto f = m.forward_row();
      const auto r = m.reverse_row();
      ASSERT_EQ(f.size(), t >= sep ? t - sep + 1 : 0);
      for (std::size_t j = 0; j < f.size(); ++j) {
        ASSERT_EQ(f[j], fwd[t][j]) << "round " << round << " forward (" << t << ", " << j << ")";
        ASSERT_EQ(r[j], rev[t][j]) << "round " << round << " reverse (" << t << ", " << j << ")";
        online_best_fwd = std::max(online_best_fwd, f[j]);
        online_best_rev = std::max(online_best_rev, r[j]);
      }
    }
    // The engine's first alignment of each pass scores the maximum of its first fill.
    align::AlignConfig ac;
    ac.gap_a = ac.gap_b = c.search.gap;
    ac.cap = c.search.cap;
    ac.self = true;
    ac.min_separation = sep;
    ac.max_alignments = 1;
    const auto source = align::ScoreSource::dense(std::span<const float>(s.values), n, n);
    const auto f1 = align::local_alignments(source, ac);
    ac.direction = Direction::reverse;
    const auto r1 = align::local_alignments(source, ac);
    EXPECT_EQ(f1.empty() ? 0.0F : f1[0].score, online_best_fwd) << "round " << round;
    EXPECT_EQ(r1.empty() ? 0.0F : r1[0].score, online_best_rev) << "round " << round;
  }
}

// Three traversals: 0..69 explore; 70..109 revisit 10..49 forwards; 110..139 revisit 65..36 backwards; 140..179
// a third pass over 10..49 that also matches the second (70..109). Revisit pairs score +1.5 (+-0.2), others -1
// (+-0.3): deterministic noise.
struct Planted {
  SimilarityMatrix s;
  std::vector<std::pair<std::size_t, std::size_t>> forward, reverse;
};

Planted planted(bool link_first_two) {
  const std::size_t n = 180;
  Planted p{SimilarityMatrix(n, n), {}, {}};
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> noise(-0.3F, 0.3F), small(-0.2F, 0.2F);
  for (auto& v : p.s.values) v = -1.0F + noise(rng);
  auto plant = [&](std::size_t i, std::size_t j, bool forward) {
    p.s(i, j) = p.s(j, i) = 1.5F + small(rng);
    (forward ? p.forward : p.reverse).emplace_back(i, j);
  };
  for (std::size_t k = 0; k < 40; ++k) {
    if (link_first_two) plant(70 + k, 10 + k, true);
    plant(140 + k, 10 + k, true);
    plant(140 + k, 70 + k, true);
  }
  for (std::size_t k = 0; k < 30; ++k) plant(110 + k, 65 - k, false);
  return p;
}

OnlineMapConfig planted_config() {
  OnlineMapConfig c;
  c.search.min_separation = 10;
  c.search.gap = 1.5F;
  c.search.cap = 20.0F;              // a cap too high lets the engine bridge one revisit to the next
  c.significance.threshold = 12.0F;  // fixed, as the engine's (no statistics)
  c.significance.max_e_value.reset();
  c.x_drop = 12.0F;
  return c;
}

struct Fed {
  std::vector<OnlineEvent> events;
  std::vector<OnlineLoopClosure> closures;
};

Fed feed(const Planted& p, const OnlineMapConfig& c) {
  OnlineMapper m(c);
  Fed out;
  for (std::size_t t = 0; t < p.s.rows; ++t) {
    auto events = m.add_scores(score_row(p.s, t, c.search.min_separation));
    for (const auto& e : events) {
      EXPECT_EQ(e.frame, t) << "events are returned with the frame that emitted them";
      if (e.kind == OnlineEventKind::loop_closure) {
        EXPECT_LE(e.i, t);
      }
    }
    out.events.insert(out.events.end(), events.begin(), events.end());
  }
  const auto last = m.finish();
  out.events.insert(out.events.end(), last.begin(), last.end());
  out.closures = m.loop_closures();
  return out;
}

TEST(OnlineMapper, PlantedRevisitsGiveTheOfflineEnginesLoopClosures) {
  const Planted p = planted(true);
  const OnlineMapConfig c = planted_config();
  const Fed online = feed(p, c);
  // The offline engine on the same scores, the same settings.
  align::AlignConfig ac;
  ac.gap_a = ac.gap_b = c.search.gap;
  ac.cap = c.search.cap;
  ac.threshold = c.significance.threshold;
  ac.self = true;
  ac.min_separation = c.search.min_separation;
  const auto offline =
      align::local_alignments_both(align::ScoreSource::dense(std::span<const float>(p.s.values), 180, 180), ac, 1);
  ASSERT_GE(offline.size(), 4U);
  std::map<std::pair<std::size_t, Direction>, std::vector<std::size_t>> online_j;  // (i, direction) -> j
  for (const auto& lc : online.closures) online_j[{lc.i, lc.direction}].push_back(lc.j);
  std::size_t offline_pairs = 0, matched = 0;
  std::set<std::tuple<std::size_t, std::size_t, Direction>> offline_cells;
  for (const auto& a : offline) {
    for (const auto& [i, j] : a.pairs) {
      ++offline_pairs;
      offline_cells.insert({i, j, a.direction});
      const auto it = online_j.find({i, a.direction});
      if (it == online_j.end()) continue;
      if (std::any_of(it->second.begin(), it->second.end(),
                      [&](std::size_t oj) { return oj + 1 >= j && oj <= j + 1; })) {
        ++matched;
      }
    }
  }
  EXPECT_GE(static_cast<double>(matched), 0.9 * static_cast<double>(offline_pairs))
      << matched << " of " << offline_pairs << " offline pairs have an online loop closure within one frame";
  // And no online loop closure away from the offline alignments.
  for (const auto& lc : online.closures) {
    bool near = false;
    for (long d = -1; d <= 1 && !near; ++d) {
      near = offline_cells.contains({lc.i, static_cast<std::size_t>(static_cast<long>(lc.j) + d), lc.direction});
    }
    EXPECT_TRUE(near) << "online loop closure " << lc.i << " ~ " << lc.j << " is on no offline alignment";
  }
  // The planted truth: every frame of the three revisits is closed, in its direction.
  for (const auto& [i, j] : p.reverse) EXPECT_TRUE(online_j.contains({i, Direction::reverse})) << i;
  std::size_t begins_forward = 0, begins_reverse = 0;
  for (const auto& e : online.events) {
    if (e.kind != OnlineEventKind::revisit_begin) continue;
    (e.direction == Direction::forward ? begins_forward : begins_reverse)++;
    EXPECT_LE(e.frame - e.first, 15U) << "a revisit is reported within 15 frames of its start";
  }
  EXPECT_EQ(begins_forward, 3U);  // 70.. ~ 10.., 140.. ~ 10.., 140.. ~ 70..
  EXPECT_EQ(begins_reverse, 1U);
}

TEST(OnlineMapper, ATrackCappedInABandFollowsTheDiagonalTheFrameScoresBest) {
  // A smooth revisit: frames 60..119 repeat 20..79, its diagonal i - j = 40 scores 1.5 and the two beside it 1.0,
  // all else -1. Once the track reaches the cap every cell of the band holds it; the frame's own scores decide,
  // and every loop closure from then on is on the revisit's own diagonal (the first maximum took diagonal 41).
  const std::size_t n = 130;
  SimilarityMatrix s(n, n);
  for (auto& v : s.values) v = -1.0F;
  for (std::size_t i = 60; i < 120; ++i) {
    for (const std::size_t d : {39U, 40U, 41U}) s(i, i - d) = s(i - d, i) = d == 40 ? 1.5F : 1.0F;
  }
  OnlineMapConfig c = planted_config();
  c.search.cap = 12.0F;
  c.significance.threshold = 8.0F;
  c.x_drop = 8.0F;
  OnlineMapper m(c);
  std::vector<OnlineEvent> closures;
  for (std::size_t t = 0; t < n; ++t) {
    for (const auto& e : m.add_scores(score_row(s, t, c.search.min_separation))) {
      if (e.kind == OnlineEventKind::loop_closure && e.direction == Direction::forward) closures.push_back(e);
    }
  }
  std::size_t capped = 0;
  for (const auto& e : closures) {
    if (e.frame < 75 || e.frame >= 120 || e.i != e.frame) continue;  // past the cap, live, inside the revisit
    ++capped;
    EXPECT_EQ(e.i - e.j, 40U) << "frame " << e.i;
  }
  EXPECT_GE(capped, 40U);
}

TEST(OnlineMapper, AThirdTraversalMergesTheFirstTwoAndLateClosuresAreWithdrawn) {
  // The second traversal does not match the first directly; the third matches both.
  const Fed linked = feed(planted(false), planted_config());
  std::size_t merges = 0, withdrawn = 0;
  for (const auto& e : linked.events) {
    if (e.kind == OnlineEventKind::place_merge) ++merges;
    if (e.kind == OnlineEventKind::correction) withdrawn += e.withdrawn.size();
  }
  EXPECT_GT(merges, 0U);
  // Closures are emitted while a track decays past the revisit's end; the corrections remove them.
  EXPECT_GT(withdrawn, 0U);
  for (const auto& lc : linked.closures) {
    EXPECT_TRUE((lc.i >= 110 && lc.i < 140) || (lc.i >= 140 && lc.i < 181)) << lc.i << " ~ " << lc.j;
  }
}

// Islands of the textbook full table: every positive cell's start cell (the first of the diagonal, vertical and
// side steps that attains it, as the engine's path rule), the best value of each start's cells; those with a
// cell in the last row have not died yet. Both tables of the self search.
// Islands whose best cell lies within `sep` columns of one of `closures` (frame, column, direction) in its
// frame, emitted by the frame at which the island died (the first row without it), are left out (a revisit's
// shadows).
std::vector<double> naive_dead_islands(const SimilarityMatrix& s, std::size_t sep, float gap, std::optional<float> cap,
                                       const std::vector<OnlineEvent>& closures = {}) {
  const std::size_t n = s.rows;
  std::vector<double> out;
  for (const bool reverse : {false, true}) {
    std::vector<std::vector<float>> h(n, std::vector<float>(n, 0.0F));
    std::vector<std::vector<std::pair<long, long>>> start(n, std::vector<std::pair<long, long>>(n, {-1, -1}));
    auto inside = [&](long r, long c) {
      return r >= 0 && c >= 0 && c < static_cast<long>(n) && r - c >= static_cast<long>(sep);
    };
    auto at = [&](long r, long c) { return inside(r, c) ? h[r][c] : 0.0F; };
    auto clamp = [&](float v) { return cap ? std::min(v, *cap) : v; };
    struct Island {
      float best = 0;
      long last = -1, best_r = -1, best_c = -1;
    };
    std::map<std::pair<long, long>, Island> islands;  // start -> its best value, its cell, its last row
    for (long r = 0; r < static_cast<long>(n); ++r) {
      for (long k = 0; k < static_cast<long>(n); ++k) {
        const long c = reverse ? static_cast<long>(n) - 1 - k : k;
        if (!inside(r, c)) continue;
        const long dc = reverse ? c + 1 : c - 1;
        const float diag = at(r - 1, dc), up = at(r - 1, c), side = at(r, dc);
        const float a = diag + s(static_cast<std::size_t>(r), static_cast<std::size_t>(c));
        const float v = clamp(std::max({0.0F, a, up - gap, side - gap}));
        h[r][c] = v;
        if (v <= 0) continue;
        if (clamp(a) == v) {
          start[r][c] = diag > 0 ? start[r - 1][dc] : std::pair{r, c};
        } else if (clamp(up - gap) == v) {
          start[r][c] = start[r - 1][c];
        } else {
          start[r][c] = start[r][dc];
        }
        auto& island = islands[start[r][c]];
        if (v > island.best) island = {v, r, r, c};
        island.last = r;
      }
    }
    for (const auto& [where, island] : islands) {
      if (island.last == static_cast<long>(n) - 1) continue;
      const bool shadow = std::any_of(closures.begin(), closures.end(), [&](const OnlineEvent& e) {
        return (e.direction == Direction::reverse) == reverse && static_cast<long>(e.frame) <= island.last + 1 &&
               static_cast<long>(e.i) == island.best_r &&
               std::abs(static_cast<long>(e.j) - island.best_c) <= static_cast<long>(sep);
      });
      if (!shadow) out.push_back(island.best);
    }
  }
  std::sort(out.begin(), out.end(), std::greater<>());
  return out;
}

SimilarityMatrix noise_scores(std::size_t n, std::uint32_t seed, float offset) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> z(0.0F, 1.0F);
  SimilarityMatrix s(n, n);
  for (auto& v : s.values) v = z(rng) - offset;
  return s;
}

TEST(OnlineMapper, IslandsAreTheTextbookTablesIslands) {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const std::size_t n = 40 + 7 * seed, sep = 1 + seed % 4;
    const SimilarityMatrix s = noise_scores(n, seed, 0.6F);
    OnlineMapConfig c;
    c.search.min_separation = sep;
    c.search.cap = seed % 2 ? std::optional<float>{3.0F} : std::nullopt;
    c.island_sample = 100000;         // keep every island
    c.significance.threshold = 2.0F;  // until the fit: revisits, whose shadows stay out of the sample
    OnlineMapper m(c);
    std::vector<OnlineEvent> closures;
    for (std::size_t t = 0; t < n; ++t) {
      for (const auto& e : m.add_scores(score_row(s, t, sep))) {
        if (e.kind == OnlineEventKind::loop_closure) closures.push_back(e);
      }
    }
    const std::vector<double> expected = naive_dead_islands(s, sep, c.search.gap, c.search.cap, closures);
    ASSERT_GT(expected.size(), 50U);
    EXPECT_EQ(m.island_scores(), expected) << "seed " << seed << ", " << closures.size() << " loop closures";
  }
}

TEST(OnlineMapper, ItsEValuesCountItsOwnChanceIslands) {
  // The meaning of the E-value (logarithmic-phase noise, mean score -0.8): in each of many runs of noise,
  // fitted on the run itself, the islands whose E-value is at most x number x on average.
  constexpr std::size_t n = 300, sep = 5;
  constexpr int runs = 40;
  OnlineMapConfig c;
  c.search.min_separation = sep;
  c.search.gap = 1.0F;
  c.search.cap.reset();
  const std::vector<double> xs = {0.5, 2.0, 8.0};
  std::vector<double> counts(xs.size(), 0.0);
  for (int r = 0; r < runs; ++r) {
    OnlineMapper m(c);
    const SimilarityMatrix s = noise_scores(n, 1000 + static_cast<std::uint32_t>(r), 0.8F);
    for (std::size_t t = 0; t < n; ++t) m.add_scores(score_row(s, t, sep));
    const auto& st = m.statistics();
    ASSERT_TRUE(st.valid());
    ASSERT_EQ(st.area, significance::search_area(n, n, true, sep, true));
    // The threshold of the last frame is the score of the E-value asked for.
    ASSERT_FLOAT_EQ(m.threshold(), static_cast<float>(st.score_at(*c.significance.max_e_value)));
    const std::vector<double> islands = m.island_scores();
    for (std::size_t k = 0; k < xs.size(); ++k) {
      const double score = st.score_at(xs[k]);
      counts[k] +=
          static_cast<double>(std::count_if(islands.begin(), islands.end(), [&](double v) { return v >= score; }));
    }
  }
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const double mean = counts[k] / runs;
    // Poisson sampling error of the mean over the runs (3 sigma), and 30 % for the model.
    EXPECT_NEAR(mean, xs[k], 0.3 * xs[k] + 3 * std::sqrt(xs[k] / runs)) << "E = " << xs[k];
  }
}

TEST(OnlineMapper, NoiseGivesNoRevisitAtTheDefaultEValue) {
  // Chance revisits over a run of N frames from frame t0 average about 2 E ln(N / t0): 0.1 per run here.
  int revisits = 0;
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const SimilarityMatrix s = noise_scores(400, seed, 0.7F);
    OnlineMapConfig c;
    OnlineMapper m(c);
    for (std::size_t t = 0; t < s.rows; ++t) {
      for (const auto& e : m.add_scores(score_row(s, t, c.search.min_separation))) {
        if (e.kind == OnlineEventKind::revisit_begin) ++revisits;
      }
    }
    EXPECT_LT(m.threshold(), c.significance.threshold) << "the statistics lower the fallback threshold of 20 on noise";
  }
  EXPECT_LE(revisits, 4);
  // With the fixed fallback threshold instead, the same runs at a threshold as low as the fit's report many.
  int fixed = 0;
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const SimilarityMatrix s = noise_scores(400, seed, 0.7F);
    OnlineMapConfig c;
    c.significance.max_e_value.reset();
    c.significance.threshold = 3.0F;
    OnlineMapper m(c);
    for (std::size_t t = 0; t < s.rows; ++t) {
      for (const auto& e : m.add_scores(score_row(s, t, c.search.min_separation))) {
        if (e.kind == OnlineEventKind::revisit_begin) ++fixed;
      }
    }
  }
  EXPECT_GT(fixed, 20);
}

TEST(OnlineMapper, AtTheEndEveryRevisitIsJudgedUnderTheWholeRunsStatistics) {
  // At a lenient E-value, chance revisits confirmed while the fit had few frames: at finish() those insignificant
  // under the last statistics are withdrawn (a correction naming why) and their frames leave the places; every loop
  // closure left belongs to a revisit at E <= max_e_value now, with that confidence.
  std::size_t withdrawn = 0, standing = 0;
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const SimilarityMatrix s = noise_scores(400, seed, 0.7F);
    OnlineMapConfig c;
    c.significance.max_e_value = 0.5;
    OnlineMapper m(c);
    std::map<std::size_t, float> best;  // revisit -> its score at its end
    for (std::size_t t = 0; t < s.rows; ++t) {
      for (const auto& e : m.add_scores(score_row(s, t, c.search.min_separation))) {
        if (e.kind == OnlineEventKind::revisit_end) best[e.revisit] = e.score;
      }
    }
    for (const auto& e : m.finish()) {
      if (e.kind == OnlineEventKind::revisit_end) best[e.revisit] = e.score;
      if (e.kind == OnlineEventKind::correction && e.reason.find("whole run") != std::string::npos) {
        withdrawn += e.withdrawn.size();
        ASSERT_GT(*e.e_value, 0.5);
      }
    }
    ASSERT_TRUE(m.statistics().valid());
    const auto places = m.places();
    std::vector<std::size_t> joined(places.size(), 0);
    for (const auto& lc : m.loop_closures()) {
      ++standing;
      ASSERT_TRUE(best.count(lc.revisit));
      const double e = m.statistics().e_value(best[lc.revisit]);
      EXPECT_LE(e, 0.5);
      EXPECT_NEAR(lc.confidence, significance::revisit_probability(e, 0.5), 1e-6);
      EXPECT_EQ(places[lc.i], places[lc.j]);
      ++joined[lc.i];
      ++joined[lc.j];
    }
    // A frame in a place of several frames is joined by a standing loop closure.
    for (std::size_t f = 0; f < places.size(); ++f) {
      if (places[f] != f) {
        EXPECT_GT(joined[f], 0U) << "seed " << seed << " frame " << f;
      }
    }
  }
  EXPECT_GT(withdrawn, 0U);
}

// Candidates at E-value x: chance ones are about as many as revisits at that E-value would be (2 x ln(N / t0) a
// run), each is confirmed or withdrawn by the end, and a true revisit's candidate comes before its revisit_begin,
// which names it.
TEST(OnlineMapper, CandidatesComeBeforeTheRevisitsTheyConfirmAndAreResolved) {
  std::size_t candidates = 0, resolved = 0;
  const int runs = 20;
  for (std::uint32_t seed = 1; seed <= static_cast<std::uint32_t>(runs); ++seed) {
    const SimilarityMatrix s = noise_scores(400, seed, 0.7F);
    OnlineMapConfig c;
    OnlineMapper m(c);
    std::vector<OnlineEvent> events;
    for (std::size_t t = 0; t < s.rows; ++t) {
      const auto e = m.add_scores(score_row(s, t, c.search.min_separation));
      events.insert(events.end(), e.begin(), e.end());
    }
    const auto last = m.finish();
    events.insert(events.end(), last.begin(), last.end());
    for (const auto& e : events) {
      if (e.kind == OnlineEventKind::revisit_candidate) {
        ++candidates;
        EXPECT_GE(e.score, 0.0F);
        ASSERT_TRUE(e.e_value.has_value());
        EXPECT_LE(*e.e_value, *c.candidate_e_value * 1.0001);
        EXPECT_GT(*e.e_value, *c.significance.max_e_value);
      }
      if (e.candidate && e.kind != OnlineEventKind::revisit_candidate) ++resolved;
    }
  }
  EXPECT_EQ(resolved, candidates) << "every candidate is confirmed or withdrawn by the end";
  const double mean = static_cast<double>(candidates) / runs;
  // About 2 ln(400 / t0) with the fit from t0 of about 50 frames: 4 (3.7 measured).
  EXPECT_GT(mean, 0.5) << "hardly a candidate at E-value 1 on noise: the level is far too strict";
  EXPECT_LT(mean, 10.0) << "chance candidates far above their E-value";

  // A revisit planted in noise: frames 450..529 see 100..179 again (scores +1.5 higher).
  SimilarityMatrix s = noise_scores(600, 3, 0.7F);
  for (std::size_t k = 0; k < 80; ++k) s(450 + k, 100 + k) = s(100 + k, 450 + k) = s(450 + k, 100 + k) + 1.5F;
  OnlineMapConfig c;
  OnlineMapper m(c);
  std::optional<OnlineEvent> candidate, begin;
  for (std::size_t t = 0; t < s.rows; ++t) {
    for (const auto& e : m.add_scores(score_row(s, t, c.search.min_separation))) {
      const bool on_it = e.i >= 450 && e.i - e.j >= 348 && e.i - e.j <= 352;
      if (e.kind == OnlineEventKind::revisit_candidate && on_it && !candidate) candidate = e;
      if (e.kind == OnlineEventKind::revisit_begin && e.i - e.j >= 340 && e.i - e.j <= 360 && !begin) begin = e;
    }
  }
  ASSERT_TRUE(candidate.has_value()) << "no candidate on the planted revisit";
  ASSERT_TRUE(begin.has_value()) << "the planted revisit was not found";
  EXPECT_LT(candidate->frame, begin->frame);
  ASSERT_TRUE(begin->candidate.has_value());
  EXPECT_EQ(*begin->candidate, *candidate->candidate);
}

TEST(OnlineMapper, DescriptorRowsAreTheDistances) {
  std::mt19937 rng(3);
  std::normal_distribution<float> g;
  OnlineMapConfig c;
  c.score.contrast_window = 0;  // the similarity as it is: -D
  c.search.min_separation = 1;
  for (auto metric : {similarity::Distance::cosine, similarity::Distance::sad}) {
    c.distance = metric;
    OnlineMapper m(c);
    std::vector<std::vector<float>> seen;
    for (int t = 0; t < 12; ++t) {
      std::vector<float> d(37);
      for (auto& v : d) v = g(rng);
      m.add_descriptor(d);
      seen.push_back(d);
      const auto row = m.last_scores();
      ASSERT_EQ(row.size(), static_cast<std::size_t>(t));
      for (int j = 0; j < t; ++j) {
        EXPECT_NEAR(row[static_cast<std::size_t>(j)],
                    -similarity::distance(metric, d, seen[static_cast<std::size_t>(j)]), 1e-5);
      }
    }
  }
}

TEST(OnlineMapper, WindowsInPlacesAreTheirFramesAtTheGivenScale) {
  // The unit is a field: 5 places of 2 frames are the 10 frames of the frame config, the window likewise, so every
  // row and event is the same; places without a scale are refused.
  std::mt19937 rng(11);
  std::normal_distribution<float> g;
  OnlineMapConfig frames;
  frames.score.contrast_window = 6;
  frames.search.min_separation = 10;
  OnlineMapConfig places = frames;
  places.unit = align::Unit::places;
  places.frames_per_place = 2.0;
  places.score.contrast_window = 3;
  places.search.min_separation = 5;
  OnlineMapper a(frames), b(places);
  EXPECT_EQ(b.config().search.min_separation, 10U);
  EXPECT_EQ(b.config().score.contrast_window, 6U);
  std::vector<std::vector<float>> route;
  for (int t = 0; t < 60; ++t) {
    std::vector<float> d(16);
    for (auto& v : d) v = g(rng);
    route.push_back(d);
  }
  for (int t = 0; t < 120; ++t) {
    auto d = route[static_cast<std::size_t>(t % 60)];
    for (auto& v : d) v += 0.3F * g(rng);
    const auto ea = a.add_descriptor(d);
    const auto eb = b.add_descriptor(d);
    ASSERT_EQ(ea.size(), eb.size()) << t;
    ASSERT_TRUE(
        std::equal(a.forward_row().begin(), a.forward_row().end(), b.forward_row().begin(), b.forward_row().end()))
        << t;
  }
  EXPECT_FALSE(a.loop_closures().empty());
  EXPECT_EQ(a.loop_closures().size(), b.loop_closures().size());
  OnlineMapConfig no_scale = places;
  no_scale.frames_per_place.reset();
  EXPECT_THROW(OnlineMapper{no_scale}, std::invalid_argument);
}

// Frames of little information online (next_frame_low_information): one pass with two dark stretches far apart
// (nearly one descriptor each, a faint drifting light) and no revisit. Unmasked, dark matches dark and the mapper
// reports a revisit; masked, none. A route driven twice through the same dark stretch keeps its revisit across it.
TEST(OnlineMapper, FramesOfLittleInformationAreNoRevisit) {
  const std::size_t dim = 24;
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.0F, 1.0F);
  const auto walk = [&](std::size_t n) {
    std::vector<std::vector<float>> out;
    std::vector<float> x(dim);
    for (auto& v : x) v = g(rng);
    for (std::size_t k = 0; k < n; ++k) {
      for (auto& v : x) v = 0.6F * v + 0.8F * g(rng);
      out.push_back(x);
    }
    return out;
  };
  const auto dark = [&](std::size_t n, float phase) {
    std::vector<std::vector<float>> out;
    for (std::size_t k = 0; k < n; ++k) {
      std::vector<float> d(dim, 0.0F);
      d[0] = 3.0F;
      d[1] = 0.3F * std::sin(0.3F * static_cast<float>(k) + phase);
      d[2] = 0.3F * std::cos(0.2F * static_cast<float>(k) + phase);
      for (auto& v : d) v += 0.05F * g(rng);
      out.push_back(d);
    }
    return out;
  };
  const auto run = [&](const std::vector<std::vector<float>>& frames, const std::vector<bool>& masked) {
    OnlineMapper m;
    for (std::size_t t = 0; t < frames.size(); ++t) {
      if (masked[t]) m.next_frame_low_information();
      m.add_descriptor(frames[t]);
    }
    m.finish();
    std::vector<std::size_t> dark;
    for (std::size_t t = 0; t < masked.size(); ++t) {
      if (masked[t]) dark.push_back(t);
    }
    EXPECT_EQ(m.low_information_frames(), dark);
    return m.loop_closures();
  };
  // One pass: 150 frames, 40 dark, 150, 40 dark, 150.
  std::vector<std::vector<float>> pass;
  std::vector<bool> masked;
  for (const auto& [part, is_dark] : {std::pair{walk(150), false},
                                      {dark(40, 0.0F), true},
                                      {walk(150), false},
                                      {dark(40, 0.0F), true},
                                      {walk(150), false}}) {
    pass.insert(pass.end(), part.begin(), part.end());
    masked.insert(masked.end(), part.size(), is_dark);
  }
  EXPECT_GT(run(pass, std::vector<bool>(pass.size(), false)).size(), 10U) << "dark must match dark unmasked";
  EXPECT_TRUE(run(pass, masked).empty());
  // The same route twice, the dark stretch in both passes at the same place: one revisit across it.
  std::vector<std::vector<float>> route = walk(120), tunnel = dark(30, 0.0F), rest = walk(120);
  std::vector<std::vector<float>> twice;
  std::vector<bool> twice_masked;
  for (int pass_no = 0; pass_no < 2; ++pass_no) {
    for (const auto* part : {&route, &tunnel, &rest}) {
      for (const auto& d : *part) {
        std::vector<float> seen = d;
        for (auto& v : seen) v += 0.2F * g(rng);
        twice.push_back(seen);
        twice_masked.push_back(part == &tunnel);
      }
    }
  }
  const auto closures = run(twice, twice_masked);
  std::size_t after_tunnel = 0;
  for (const auto& c : closures) {
    EXPECT_LE(std::abs(static_cast<long>(c.i) - static_cast<long>(c.j) - 270L), 3L) << c.i << " " << c.j;
    after_tunnel += c.i >= 270 + 150 + 10 ? 1 : 0;
  }
  EXPECT_GT(after_tunnel, 80U) << "the revisit goes on after the tunnel";
}

TEST(OnlineMapper, RefusesBadFrames) {
  OnlineMapper m;
  EXPECT_THROW(m.add_scores(std::vector<float>{1.0F}), std::invalid_argument);  // frame 0 has no scores
  m.add_descriptor(std::vector<float>{1, 2, 3});
  EXPECT_THROW(m.add_descriptor(std::vector<float>{1, 2}), std::invalid_argument);
  EXPECT_THROW(m.add_descriptor(std::vector<float>{1, NAN, 3}), std::invalid_argument);
  EXPECT_THROW(m.add_similarity(std::vector<float>{0.5F}), std::invalid_argument);  // after descriptors
  OnlineMapConfig bad;
  bad.significance.threshold = 50;  // above the cap
  EXPECT_THROW(OnlineMapper{bad}, std::invalid_argument);
  for (const double e : {0.0, -1.0, static_cast<double>(NAN)}) {
    OnlineMapConfig no_e;
    no_e.significance.max_e_value = e;
    EXPECT_THROW(OnlineMapper{no_e}, std::invalid_argument) << e;
  }
  OnlineMapConfig tiny;
  tiny.island_sample = 10;
  EXPECT_THROW(OnlineMapper{tiny}, std::invalid_argument);
}

namespace {

// Descriptors of no revisit: AR(1) Gaussian vectors, x_t = rho x_{t-1} + sqrt(1 - rho^2) e_t (rho = 0: white
// noise).
std::vector<std::vector<float>> noise_descriptors(std::size_t n, double rho, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  std::vector<float> x(128);
  for (auto& v : x) v = normal(rng);
  std::vector<std::vector<float>> out;
  while (out.size() < n) {
    for (auto& v : x) v = static_cast<float>(rho) * v + static_cast<float>(std::sqrt(1 - rho * rho)) * normal(rng);
    out.push_back(x);
  }
  return out;
}

struct NoiseRun {
  std::size_t closures = 0;
  float offset = 0;
  std::vector<OnlineMapper::OffsetChange> changes;
};

NoiseRun map_noise(const std::vector<std::vector<float>>& frames, const OnlineMapConfig& c) {
  OnlineMapper m(c);
  for (const auto& f : frames) m.add_descriptor(f);
  m.finish();
  return {m.loop_closures().size(), m.contrast_offset(), m.offset_changes()};
}

}  // namespace

// White-noise descriptors put the default offset's chance paths in the linear phase: they grow through the whole
// run and reach any threshold (offline, the map raises its offset for them too). The global alignment rate of the
// first scores shows it, and the mapper raises the offset before the paths have grown; without the check the
// same runs report chance revisits.
TEST(OnlineMapper, ScoresInTheLinearPhaseRaiseTheOffset) {
  std::size_t with = 0, without = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const auto frames = noise_descriptors(300, 0.0, seed);
    OnlineMapConfig c;
    const NoiseRun adapted = map_noise(frames, c);
    ASSERT_FALSE(adapted.changes.empty()) << "seed " << seed;
    EXPECT_EQ(adapted.changes[0].check, "scores");
    EXPECT_GT(adapted.changes[0].global_rate, -0.1);
    EXPECT_LT(adapted.changes[0].frame, 100U) << "2,048 scores are in by frame 73";
    EXPECT_GT(adapted.offset, c.score.contrast_offset);
    EXPECT_FLOAT_EQ(adapted.changes[0].to - adapted.changes[0].from, c.phase.contrast_offset_step);
    with += adapted.closures;
    c.phase.adapt_offset = false;
    const NoiseRun fixed = map_noise(frames, c);
    EXPECT_TRUE(fixed.changes.empty());
    EXPECT_FLOAT_EQ(fixed.offset, c.score.contrast_offset);
    without += fixed.closures;
  }
  // A chance revisit at E = 0.01 may still come (one run of the six here, 11 loop closures).
  EXPECT_LE(20 * with, without) << "chance loop closures on white noise";
  EXPECT_GT(without, 100U) << "the runs no longer need the check: the test shows nothing";
}

// Without the scores' check, the islands show the same phase, later: their median length in places passes the
// logarithmic phase's bound after about 220 frames, and the offset is raised then.
TEST(OnlineMapper, ChanceIslandsInTheLinearPhaseRaiseTheOffset) {
  std::size_t with = 0, without = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const auto frames = noise_descriptors(300, 0.0, seed);
    OnlineMapConfig c;
    c.phase.max_global_rate.reset();
    const NoiseRun adapted = map_noise(frames, c);
    ASSERT_FALSE(adapted.changes.empty()) << "seed " << seed;
    const auto& change = adapted.changes[0];
    EXPECT_EQ(change.check, "islands");
    EXPECT_GT(change.chance_length, change.bound);
    EXPECT_NEAR(change.frames_per_place, 1.0, 0.2) << "white noise: a place a frame";
    with += adapted.closures;
    c.phase.adapt_offset = false;
    without += map_noise(frames, c).closures;
  }
  EXPECT_LE(10 * with, without);
}

// The same white noise from an offset of 1: its chance paths stay short (the logarithmic phase), so the check
// leaves the offset alone.
TEST(OnlineMapper, TheLogarithmicPhaseKeepsTheOffset) {
  OnlineMapConfig c;
  c.score.contrast_offset = 1.0F;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    const NoiseRun run = map_noise(noise_descriptors(300, 0.0, seed), c);
    EXPECT_TRUE(run.changes.empty()) << "seed " << seed;
    EXPECT_FLOAT_EQ(run.offset, c.score.contrast_offset);
    EXPECT_EQ(run.closures, 0U) << "seed " << seed;
  }
}

// A run too short for the islands: the statistics come from the offline fit of its table so far, and a planted
// revisit is reported at their E-value, sooner than at the fallback threshold of 20.
TEST(OnlineMapper, AShortRunIsFittedOnItsTableUntilTheIslandsSuffice) {
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  auto frames = noise_descriptors(130, 0.0, 21);
  for (std::size_t t = 80; t < 125; ++t) {  // frames 80..124 revisit 10..54
    for (std::size_t k = 0; k < frames[t].size(); ++k) frames[t][k] = frames[t - 70][k] + 1.5F * normal(rng);
  }
  const auto first_begin = [&](const OnlineMapConfig& c, OnlineMapper& m) {
    std::optional<std::size_t> at;
    for (const auto& f : frames) {
      for (const auto& e : m.add_descriptor(f)) {
        if (e.kind == OnlineEventKind::revisit_begin && !at) {
          EXPECT_EQ(e.i - e.j, 70U) << "on the planted diagonal";
          at = e.frame;
        }
      }
    }
    EXPECT_EQ(m.contrast_offset(), c.score.contrast_offset) << "the logarithmic phase";
    return at;
  };
  OnlineMapConfig c;
  c.score.contrast_offset = 1.0F;  // white noise's logarithmic phase (TheLogarithmicPhaseKeepsTheOffset)
  OnlineMapper early(c);
  const auto with = first_begin(c, early);
  ASSERT_TRUE(with.has_value());
  EXPECT_LE(*with, 80U + 10U) << "reported within 10 frames of the revisit's start";
  ASSERT_TRUE(early.statistics().valid());
  EXPECT_TRUE(early.statistics_from_table()) << "130 frames leave too few dead islands";
  EXPECT_EQ(early.statistics().area, significance::search_area(130, 130, true, c.search.min_separation, true));
  EXPECT_FLOAT_EQ(early.threshold(), static_cast<float>(early.statistics().score_at(*c.significance.max_e_value)));
  EXPECT_LT(early.threshold(), c.significance.threshold);
  // Every loop closure on the planted diagonal; a few may run past its ends, where the path began or ended on
  // chance cells (docs/online.md).
  std::size_t on = 0, inside = 0;
  for (const auto& lc : early.loop_closures()) {
    if (lc.i - lc.j < 69 || lc.i - lc.j > 71) continue;
    ++on;
    inside += lc.i >= 80 && lc.i < 125;
  }
  EXPECT_EQ(early.loop_closures().size(), on) << "no loop closure off the revisit";
  EXPECT_GE(inside, 40U);
  EXPECT_LE(on - inside, 4U);

  c.early_fit_frames = 0;
  OnlineMapper fixed(c);
  const auto without = first_begin(c, fixed);
  EXPECT_FALSE(fixed.statistics().valid());
  EXPECT_EQ(fixed.threshold(), c.significance.threshold);
  ASSERT_TRUE(without.has_value());
  EXPECT_GT(*without, *with + 5) << "the fallback threshold of 20 takes longer to reach";
}

// The early statistics keep their E-value on noise: over 100 runs of 150 white-noise frames, revisits begin no
// more often than about 2 E ln(N / t0) a run (t0 = 50, where the first fits come); the fixed threshold never
// lets one through in so short a run, and the early fit was used in every run.
TEST(OnlineMapper, TheEarlyFitKeepsItsEValueOnNoise) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("many noise sequences");
  for (const double e : {0.01, 0.1}) {
    OnlineMapConfig c;
    c.score.contrast_offset = 1.0F;
    c.significance.max_e_value = e;
    c.candidate_e_value.reset();
    std::size_t begins = 0, fitted = 0;
    constexpr int runs = 100;
    for (int r = 0; r < runs; ++r) {
      OnlineMapper m(c);
      for (const auto& f : noise_descriptors(150, 0.0, 1000 + static_cast<std::uint32_t>(r))) {
        for (const auto& ev : m.add_descriptor(f)) begins += ev.kind == OnlineEventKind::revisit_begin;
      }
      fitted += m.statistics_from_table();
    }
    EXPECT_EQ(fitted, static_cast<std::size_t>(runs)) << "E = " << e;
    const double expected = runs * 2 * e * std::log(150.0 / 50.0);
    EXPECT_LE(static_cast<double>(begins), expected + 3 * std::sqrt(expected) + 1) << "E = " << e;
  }
}

}  // namespace
}  // namespace seqtopo::mapping
