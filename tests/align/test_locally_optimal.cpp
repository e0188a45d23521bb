// The locally optimal alignment set against its definition (locally_optimal.hpp), checked literally by
// enumerating every path of small grids, and its invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include "random_problems.hpp"
#include "seqtopo/align/locally_optimal.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

using align::AlignConfig;
using align::Direction;
using align::LocalAlignment;

// Every path of the grid graph of one pass, and the locally optimal ones found by checking each condition of
// the definition on every sub-path and every enclosing path. Exponential: grids up to 6 x 6.
class BruteForce {
 public:
  BruteForce(const std::vector<std::vector<float>>& s, const AlignConfig& c) : c_(c), m_(s.size()) {
    n_ = m_ == 0 ? 0 : s[0].size();
    w_.assign(m_ + 1, std::vector<float>(n_ + 1, 0.0F));
    for (std::size_t i = 1; i <= m_; ++i) {
      for (std::size_t j = 1; j <= n_; ++j) w_[i][j] = s[i - 1][col(j)];
    }
  }

  std::vector<LocalAlignment> run() {
    for (std::size_t i = 0; i <= m_; ++i) {
      for (std::size_t j = 0; j <= n_; ++j) {
        Path p;
        p.vertices.push_back({i, j});
        extend(p);
      }
    }
    // Best admissible score from u to x.
    std::map<std::pair<Vertex, Vertex>, float> best;
    for (const Path& p : paths_) {
      if (!p.admissible) continue;
      auto [it, fresh] = best.try_emplace({p.vertices.front(), p.vertices.back()}, p.running.back());
      if (!fresh) it->second = std::max(it->second, p.running.back());
    }
    // The best score of an admissible path strictly containing each path (by its key).
    std::map<std::string, float> enclosing;
    for (const Path& r : paths_) {
      if (!r.admissible) continue;
      const std::size_t k = r.steps.size();
      for (std::size_t a = 0; a < k; ++a) {
        for (std::size_t b = a + 1; b <= k; ++b) {
          if (a == 0 && b == k) continue;
          auto [it, fresh] = enclosing.try_emplace(key(r, a, b), r.running.back());
          if (!fresh) it->second = std::max(it->second, r.running.back());
        }
      }
    }
    // Canonical paths: tight everywhere, first in the step order from the end backwards.
    std::map<std::pair<Vertex, Vertex>, const Path*> canonical;
    for (const Path& p : paths_) {
      if (!p.admissible) continue;
      bool tight = true;
      for (std::size_t t = 1; t < p.vertices.size(); ++t) {
        tight = tight && p.running[t - 1] == best.at({p.vertices.front(), p.vertices[t]});
      }
      if (!tight) continue;
      auto [it, fresh] = canonical.try_emplace({p.vertices.front(), p.vertices.back()}, &p);
      if (!fresh && reversed_less(p, *it->second)) it->second = &p;
    }
    std::vector<LocalAlignment> out;
    const float floor = std::max(c_.threshold, std::numeric_limits<float>::min());
    for (const auto& [ends, p] : canonical) {
      const float score = p->running.back();
      if (score < floor) continue;
      bool ok = true;
      const std::size_t k = p->steps.size();
      for (std::size_t a = 0; a < k && ok; ++a) {  // (1) every sub-path scores at most as much
        for (std::size_t b = a + 1; b <= k && ok; ++b) ok = sub_score(*p, a, b) <= score;
      }
      if (const auto it = enclosing.find(key(*p, 0, k)); ok && it != enclosing.end()) ok = it->second < score;  // (2)
      if (ok) out.push_back(alignment(*p));
    }
    return out;
  }

 private:
  using Vertex = std::pair<std::size_t, std::size_t>;
  struct Path {
    std::vector<Vertex> vertices;
    std::vector<int> steps;      // 1 diagonal, 2 vertical, 3 horizontal
    std::vector<float> weights;  // of the steps
    std::vector<float> running;  // capped cumulative score after each step
    bool admissible = true;
  };

  std::size_t col(std::size_t j) const { return c_.direction == Direction::forward ? j - 1 : n_ - j; }
  bool enterable(std::size_t i, std::size_t j) const {
    if (i < 1 || j < 1 || i > m_ || j > n_) return false;
    if (!c_.self) return true;
    const std::size_t r = i - 1, cc = col(j);
    return r >= cc + c_.min_separation;
  }
  float clamp(float v) const { return c_.cap ? std::min(v, *c_.cap) : v; }

  void extend(Path& p) {
    const auto [i, j] = p.vertices.back();
    const std::pair<int, Vertex> next[] = {{1, {i + 1, j + 1}}, {2, {i + 1, j}}, {3, {i, j + 1}}};
    for (const auto& [step, v] : next) {
      if (!enterable(v.first, v.second)) continue;
      const float w = step == 1 ? w_[v.first][v.second] : step == 2 ? -c_.gap_a : -c_.gap_b;
      Path q = p;
      q.vertices.push_back(v);
      q.steps.push_back(step);
      q.weights.push_back(w);
      q.running.push_back(clamp((p.running.empty() ? 0.0F : p.running.back()) + w));
      q.admissible = p.admissible && q.running.back() > 0;
      paths_.push_back(q);
      extend(q);
    }
  }

  // Steps [a, b) of p.
  std::string key(const Path& p, std::size_t a, std::size_t b) const {
    std::string k = std::to_string(p.vertices[a].first) + "," + std::to_string(p.vertices[a].second) + ":";
    for (std::size_t t = a; t < b; ++t) k += static_cast<char>('0' + p.steps[t]);
    return k;
  }
  float sub_score(const Path& p, std::size_t a, std::size_t b) const {
    float r = 0;
    for (std::size_t t = a; t < b; ++t) r = clamp(r + p.weights[t]);
    return r;
  }
  static bool reversed_less(const Path& x, const Path& y) {
    return std::lexicographical_compare(x.steps.rbegin(), x.steps.rend(), y.steps.rbegin(), y.steps.rend());
  }
  LocalAlignment alignment(const Path& p) const {
    LocalAlignment a;
    a.score = p.running.back();
    a.direction = c_.direction;
    for (std::size_t t = 0; t < p.steps.size(); ++t) {
      if (p.steps[t] == 1) a.pairs.emplace_back(p.vertices[t + 1].first - 1, col(p.vertices[t + 1].second));
    }
    a.a_begin = a.pairs.front().first;
    a.a_end = a.pairs.back().first + 1;
    a.b_begin = std::min(a.pairs.front().second, a.pairs.back().second);
    a.b_end = std::max(a.pairs.front().second, a.pairs.back().second) + 1;
    return a;
  }

  AlignConfig c_;
  std::size_t m_, n_;
  std::vector<std::vector<float>> w_;  // weight of the diagonal step into (i, j)
  std::vector<Path> paths_;
};

void sort_best_first(std::vector<LocalAlignment>& v) {
  std::sort(v.begin(), v.end(), [](const LocalAlignment& x, const LocalAlignment& y) {
    if (x.score != y.score) return x.score > y.score;
    if (x.a_begin != y.a_begin) return x.a_begin < y.a_begin;
    if (x.b_begin != y.b_begin) return x.b_begin < y.b_begin;
    if (x.a_end != y.a_end) return x.a_end < y.a_end;
    if (x.b_end != y.b_end) return x.b_end < y.b_end;
    return x.pairs < y.pairs;
  });
}

std::string describe(const test_support::RandomProblem& p) {
  const auto& c = p.naive.config;
  std::string d = std::to_string(p.rows) + "x" + std::to_string(p.cols) + " gaps " + std::to_string(c.gap_a) + "/" +
                  std::to_string(c.gap_b) + " cap " + (c.cap ? std::to_string(*c.cap) : "none") + " threshold " +
                  std::to_string(c.threshold) + (c.self ? " self sep " + std::to_string(c.min_separation) : "") + " " +
                  std::string(to_string(c.direction)) + "\n";
  for (const auto& row : p.naive.s) {
    for (float v : row) d += std::to_string(v) + " ";
    d += "\n";
  }
  return d;
}

TEST(LocallyOptimal, EqualsTheDefinitionOnEveryPathOfSmallGrids) {
  std::mt19937 rng(17);
  std::size_t found = 0, shared = 0, capped = 0;
  for (int k = 0; k < 1200; ++k) {
    const auto p = test_support::random_problem(rng, k < 1000 ? 5 : 6);
    auto expected = BruteForce(p.naive.s, p.naive.config).run();
    sort_best_first(expected);
    const auto got = align::locally_optimal_alignments(p.source(), p.naive.config);
    ASSERT_EQ(got, expected) << describe(p);
    found += got.size();
    if (p.naive.config.cap) capped += got.size();
    std::set<std::pair<std::size_t, std::size_t>> seen;
    for (const auto& a : got) {
      for (const auto& pair : a.pairs) shared += seen.insert(pair).second ? 0 : 1;
    }
  }
  // The comparison must have covered the cases that matter: many alignments, some capped, some sharing pairs.
  EXPECT_GT(found, 1200U);
  EXPECT_GT(capped, 300U);
  EXPECT_GT(shared, 150U);
}

TEST(LocallyOptimal, MaxAlignmentsKeepsTheBestFirst) {
  std::mt19937 rng(5);
  for (int k = 0; k < 100; ++k) {
    auto p = test_support::random_problem(rng, 12);
    const auto all = align::locally_optimal_alignments(p.source(), p.naive.config);
    p.naive.config.max_alignments = 3;
    const auto some = align::locally_optimal_alignments(p.source(), p.naive.config);
    ASSERT_EQ(some.size(), std::min<std::size_t>(3, all.size()));
    EXPECT_TRUE(std::equal(some.begin(), some.end(), all.begin()));
  }
}

TEST(LocallyOptimal, BestScoreIsTheEnginesBestScore) {
  std::mt19937 rng(6);
  for (int k = 0; k < 300; ++k) {
    const auto p = test_support::random_problem(rng, 20);
    const auto lo = align::locally_optimal_alignments(p.source(), p.naive.config);
    const auto ni = align::local_alignments(p.source(), p.naive.config);
    ASSERT_EQ(lo.empty(), ni.empty()) << describe(p);
    if (!lo.empty()) {
      EXPECT_EQ(lo.front().score, ni.front().score) << describe(p);
    }
  }
}

TEST(LocallyOptimal, SameResultForAnyThreadCountAndAnySource) {
  std::mt19937 rng(7);
  for (int k = 0; k < 100; ++k) {
    const auto p = test_support::random_problem(rng, 20);
    const auto one = align::locally_optimal_alignments_both(p.source(), p.naive.config, 1);
    const auto two = align::locally_optimal_alignments_both(p.source(), p.naive.config, 2);
    EXPECT_EQ(one, two);
    const auto& dense = p.dense;
    const std::size_t cols = p.cols;
    const auto function = align::ScoreSource::function(
        p.rows, p.cols, [&dense, cols](std::size_t i, std::size_t j) { return dense[i * cols + j]; });
    EXPECT_EQ(align::locally_optimal_alignments_both(function, p.naive.config, 2), one);
  }
}

TEST(LocallyOptimal, EqualScoresComeInTheDocumentedOrder) {
  // All-equal scores: every alignment ties with many others, so only the stated order decides.
  std::vector<float> s(64, 1.0F);
  AlignConfig c;
  c.gap_a = c.gap_b = 0.5F;
  c.cap = 3.0F;
  const auto both = align::locally_optimal_alignments_both(align::ScoreSource::dense(s, 8, 8), c, 2);
  ASSERT_GT(both.size(), 2U);
  for (std::size_t k = 1; k < both.size(); ++k) {
    const auto& x = both[k - 1];
    const auto& y = both[k];
    const auto key = [](const LocalAlignment& a) {
      return std::make_tuple(-a.score, a.direction == Direction::forward ? 0 : 1, a.a_begin, a.b_begin, a.a_end,
                             a.b_end, a.pairs);
    };
    EXPECT_LT(key(x), key(y)) << k;
  }
}

TEST(LocallyOptimal, CapSplitsRevisitsThatTheUncappedSumJoins) {
  // Two matching stretches of 5 (+2 each) separated by 3 mismatching pairs (-2 each): the uncapped sum joins
  // them (10 - 6 + 10 > 10); a cap of 4 does not carry across a stretch of -6.
  const std::size_t n = 13;
  std::vector<float> s(n * n, -2.0F);
  for (std::size_t k = 0; k < n; ++k) s[k * n + k] = (k >= 5 && k < 8) ? -2.0F : 2.0F;
  AlignConfig c;
  c.gap_a = c.gap_b = 5.0F;
  const auto joined = align::locally_optimal_alignments(align::ScoreSource::dense(s, n, n), c);
  ASSERT_FALSE(joined.empty());
  EXPECT_EQ(joined.front().a_begin, 0U);
  EXPECT_EQ(joined.front().a_end, n);
  c.cap = 4.0F;
  const auto split = align::locally_optimal_alignments(align::ScoreSource::dense(s, n, n), c);
  ASSERT_EQ(split.size(), 2U);
  EXPECT_EQ(split[0].a_begin, 0U);
  EXPECT_EQ(split[0].a_end, 5U);
  EXPECT_EQ(split[1].a_begin, 8U);
  EXPECT_EQ(split[1].a_end, n);
}

TEST(LocallyOptimal, BadInputThrows) {
  std::vector<float> s(6, 1.0F);
  AlignConfig c;
  c.self = true;
  EXPECT_THROW(align::locally_optimal_alignments(align::ScoreSource::dense(s, 2, 3), c), std::invalid_argument);
  c.self = false;
  c.gap_a = -1;
  EXPECT_THROW(align::locally_optimal_alignments(align::ScoreSource::dense(s, 2, 3), c), std::invalid_argument);
  EXPECT_EQ(align::parse_alignment_set("locally-optimal"), align::AlignmentSet::locally_optimal);
  EXPECT_EQ(align::parse_alignment_set("non-intersecting"), align::AlignmentSet::non_intersecting);
  try {
    align::parse_alignment_set("all");
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("locally-optimal or non-intersecting"), std::string::npos);
  }
}

}  // namespace
}  // namespace seqtopo
