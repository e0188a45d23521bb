// The sparse alignment's steps (components, one box each, the merge) composed in any order and any
// partition into groups of "ranks" give exactly sparse_local_alignments_both; the dealing of components
// to ranks.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "scale/random_sparse_problems.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_components.hpp"

namespace seqtopo::scale {
namespace {

using align::LocalAlignment;
using test_problems::Problem;
using test_problems::random_problem;

// What P ranks would do: each aligns its components (owner[k] == rank) in a shuffled order, and the
// lists are gathered rank by rank (in a shuffled rank order too) before the merge.
std::vector<LocalAlignment> run_on_ranks(const SparseScores& scores, const align::AlignConfig& config,
                                         const std::vector<SparseComponent>& components,
                                         const std::vector<std::size_t>& owner, std::size_t ranks, std::mt19937& rng) {
  std::vector<std::size_t> rank_order(ranks);
  std::iota(rank_order.begin(), rank_order.end(), std::size_t{0});
  std::shuffle(rank_order.begin(), rank_order.end(), rng);
  std::vector<SparseComponent> gathered;
  std::vector<std::vector<LocalAlignment>> aligned;
  for (const std::size_t rank : rank_order) {
    std::vector<std::size_t> mine;
    for (std::size_t k = 0; k < components.size(); ++k) {
      if (owner[k] == rank) mine.push_back(k);
    }
    std::shuffle(mine.begin(), mine.end(), rng);
    for (const std::size_t k : mine) {
      gathered.push_back(components[k]);
      aligned.push_back(align_component(scores, config, components[k]));
    }
  }
  return merge_component_alignments_both(scores, config, gathered, std::move(aligned));
}

// Alignments of one pass next to each other with equal score, a_begin and b_begin: the cases the
// merge orders by the first maximal cell.
std::size_t key_ties(const std::vector<LocalAlignment>& alignments) {
  std::size_t ties = 0;
  for (std::size_t k = 1; k < alignments.size(); ++k) {
    const auto& a = alignments[k - 1];
    const auto& b = alignments[k];
    const bool tie =
        a.direction == b.direction && a.score == b.score && a.a_begin == b.a_begin && a.b_begin == b.b_begin;
    ties += tie ? 1 : 0;
  }
  return ties;
}

void expect_consistent(const SparseScores& scores, const align::AlignConfig& config,
                       const std::vector<SparseComponent>& components) {
  std::size_t expected_order[2] = {0, 0};
  for (const SparseComponent& c : components) {
    const bool fwd = c.direction == align::Direction::forward;
    EXPECT_EQ(c.order, expected_order[fwd ? 0 : 1]++);
    ASSERT_EQ(c.run_begin.size(), c.row_end - c.row_begin + 1);
    EXPECT_EQ(c.run_begin.front(), 0U);
    EXPECT_EQ(c.run_begin.back(), c.runs.size());
    EXPECT_GE(c.best, std::max(config.threshold, 1e-30F));
    for (std::size_t i = c.row_begin; i < c.row_end; ++i) {
      const std::size_t first = c.run_begin[i - c.row_begin], last = c.run_begin[i - c.row_begin + 1];
      if (i == c.row_begin || i + 1 == c.row_end) {
        EXPECT_LT(first, last) << "the box's first and last rows have cells";
      }
      for (std::size_t k = first; k < last; ++k) {
        const SparseRun run = c.runs[k];
        ASSERT_GT(run.length, 0U);
        if (k > first) {
          EXPECT_GT(run.pass_col, c.runs[k - 1].pass_col + c.runs[k - 1].length) << "runs never touch";
        }
        EXPECT_FALSE(run.pass_col > 0 && c.contains(i, run.pass_col - 1));
        EXPECT_FALSE(c.contains(i, std::size_t{run.pass_col} + run.length));
        for (std::size_t t = run.pass_col; t < std::size_t{run.pass_col} + run.length; ++t) {
          EXPECT_TRUE(t >= c.pass_col_begin && t < c.pass_col_end);
          EXPECT_TRUE(c.contains(i, t));
          const std::size_t j = fwd ? t : scores.cols() - 1 - t;
          EXPECT_TRUE(i >= c.box_row_begin && i < c.box_row_end && j >= c.box_col_begin && j < c.box_col_end);
        }
      }
    }
    EXPECT_FALSE(c.contains(c.row_begin - 1, c.pass_col_begin));
    EXPECT_FALSE(c.contains(c.row_end, c.pass_col_begin));
    if (c.kind == SparseBoxKind::diagonal_square) {
      EXPECT_TRUE(config.self);
      EXPECT_EQ(c.box_row_begin, c.box_col_begin);
      EXPECT_EQ(c.box_row_end, c.box_col_end);
    }
  }
}

// The first fill on every cell of the pass (the engine's recurrence, H = 0 outside the self band), its
// positive cells split into the components of the recurrence, those reaching the threshold kept, in the
// row-major order of their first cells: what sparse_components must return, as sets of cells.
std::vector<std::vector<std::pair<std::size_t, std::size_t>>> reference_components(const SparseScores& s,
                                                                                   const align::AlignConfig& config) {
  const std::size_t m = s.rows(), n = s.cols();
  const bool fwd = config.direction == align::Direction::forward;
  std::vector<float> h((m + 1) * (n + 1), 0.0F);
  auto at = [&](std::size_t i, std::size_t t) -> float& { return h[(i + 1) * (n + 1) + t + 1]; };  // -1 allowed
  std::vector<std::size_t> parent(m * n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t t = 0; t < n; ++t) {
      const std::size_t j = fwd ? t : n - 1 - t;
      if (config.self && !(i >= j && i - j >= config.min_separation)) continue;
      float v = 0.0F;
      v = std::max(v, at(i - 1, t - 1) + s.at(i, j));
      v = std::max(v, at(i - 1, t) - config.gap_a);
      v = std::max(v, at(i, t - 1) - config.gap_b);
      if (config.cap) v = std::min(v, *config.cap);
      at(i, t) = v;
      if (!(v > 0)) continue;
      const std::pair<std::size_t, std::size_t> preds[] = {{i - 1, t - 1}, {i - 1, t}, {i, t - 1}};
      for (const auto& [pi, pt] : preds) {
        if (pi < m && pt < n && at(pi, pt) > 0) {
          const std::size_t a = find(i * n + t), b = find(pi * n + pt);
          parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
  }
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> out;
  std::vector<std::size_t> index_of(m * n, parent.size());
  std::vector<float> best;
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t t = 0; t < n; ++t) {
      if (!(at(i, t) > 0)) continue;
      const std::size_t root = find(i * n + t);
      if (index_of[root] == parent.size()) {
        index_of[root] = out.size();
        out.emplace_back();
        best.push_back(0.0F);
      }
      out[index_of[root]].emplace_back(i, t);
      best[index_of[root]] = std::max(best[index_of[root]], at(i, t));
    }
  }
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> kept;
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (best[k] >= std::max(config.threshold, std::numeric_limits<float>::min())) kept.push_back(std::move(out[k]));
  }
  return kept;
}

std::vector<std::pair<std::size_t, std::size_t>> cells_of(const SparseComponent& c) {
  std::vector<std::pair<std::size_t, std::size_t>> cells;
  for (std::size_t i = c.row_begin; i < c.row_end; ++i) {
    for (std::size_t k = c.run_begin[i - c.row_begin]; k < c.run_begin[i - c.row_begin + 1]; ++k) {
      for (std::uint32_t d = 0; d < c.runs[k].length; ++d) cells.emplace_back(i, c.runs[k].pass_col + d);
    }
  }
  return cells;
}

TEST(SparseComponents, AreThoseOfTheFullFirstFill) {
  std::mt19937 rng(20260518);
  std::size_t components = 0, multi_run_rows = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Problem p = random_problem(rng, trial % 2 == 0);
    for (const auto dir : {align::Direction::forward, align::Direction::reverse}) {
      auto cfg = p.config;
      cfg.direction = dir;
      const auto got = sparse_components(p.scores, cfg);
      const auto want = reference_components(p.scores, cfg);
      ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
      for (std::size_t k = 0; k < got.size(); ++k) {
        ASSERT_EQ(cells_of(got[k]), want[k]) << "trial " << trial << ", component " << k;
        for (std::size_t r = 0; r + 1 < got[k].run_begin.size(); ++r) {
          multi_run_rows += got[k].run_begin[r + 1] - got[k].run_begin[r] > 1 ? 1 : 0;
        }
      }
      components += got.size();
    }
  }
  EXPECT_GT(components, 500U);
  EXPECT_GT(multi_run_rows, 0U);  // rows where a component has cells apart
}

TEST(SparseComponents, AnyOrderAndAnyRanksEqualOneProcessOnRandomCases) {
  std::mt19937 rng(20261124);
  std::mt19937 shuffle(7);
  std::size_t nonempty = 0, multi = 0, ties = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Problem p = random_problem(rng, trial % 2 == 0);
    if (trial % 7 == 3) p.config.max_alignments = 1 + static_cast<std::size_t>(trial % 4);
    SparseAlignStats want_stats, got_stats;
    const auto expected = sparse_local_alignments_both(p.scores, p.config, 1, &want_stats);
    const auto components = sparse_components_both(p.scores, p.config, trial % 3 == 0 ? 2U : 1U, &got_stats);
    expect_consistent(p.scores, p.config, components);
    EXPECT_EQ(got_stats.active_cells, want_stats.active_cells);
    EXPECT_EQ(got_stats.components, want_stats.components);
    EXPECT_EQ(got_stats.aligned_components, components.size());
    EXPECT_EQ(got_stats.box_cells, want_stats.box_cells);
    for (const std::size_t ranks : {1U, 2U, 3U, 5U}) {
      const auto dealt = deal_components(components, ranks);
      ASSERT_EQ(run_on_ranks(p.scores, p.config, components, dealt, ranks, shuffle), expected)
          << "trial " << trial << ", " << ranks << " ranks, dealt";
      std::vector<std::size_t> random_owner(components.size());
      for (auto& o : random_owner) o = std::uniform_int_distribution<std::size_t>(0, ranks - 1)(shuffle);
      ASSERT_EQ(run_on_ranks(p.scores, p.config, components, random_owner, ranks, shuffle), expected)
          << "trial " << trial << ", " << ranks << " ranks, random owners";
    }
    // One pass alone, components reversed.
    for (const auto dir : {align::Direction::forward, align::Direction::reverse}) {
      auto cfg = p.config;
      cfg.direction = dir;
      auto pass = sparse_components(p.scores, cfg);
      std::reverse(pass.begin(), pass.end());
      std::vector<std::vector<LocalAlignment>> aligned;
      for (const auto& c : pass) aligned.push_back(align_component(p.scores, cfg, c));
      ASSERT_EQ(merge_component_alignments(p.scores, cfg, pass, std::move(aligned)),
                sparse_local_alignments(p.scores, cfg))
          << "trial " << trial;
    }
    nonempty += expected.empty() ? 0 : 1;
    multi += components.size() > 1 ? 1 : 0;
    ties += key_ties(expected);
  }
  EXPECT_GT(nonempty, 150U);
  EXPECT_GT(multi, 100U);
  EXPECT_GT(ties, 0U);  // the merge's tie rule between components is exercised
}

// A self-similarity with planted revisits, forward and backward, of equal integer scores (many equal
// capped scores across components), and scattered noise.
SparseScores planted_revisits(std::size_t n, std::mt19937& rng) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  std::vector<SparseEntry> entries;
  auto add = [&](std::size_t i, std::size_t j, float v) {
    if (i >= n || j >= n || i == j) return;
    if (!seen.insert({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)}).second) return;
    seen.insert({static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i)});
    entries.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), v});
    entries.push_back({static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i), v});
  };
  std::uniform_int_distribution<std::size_t> pos(0, n - 1), len(15, 80);
  for (int r = 0; r < 12; ++r) {
    const std::size_t i0 = pos(rng), j0 = pos(rng), l = len(rng);
    const bool backward = r % 2 == 1;
    for (std::size_t k = 0; k < l; ++k) {
      if (std::bernoulli_distribution(0.08)(rng)) continue;
      const std::size_t j = backward ? j0 - k : j0 + k;  // wraps out of range when it runs off
      add(i0 + k, j, 2.0F);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 4; ++k) add(i, pos(rng), static_cast<float>(std::uniform_int_distribution<int>(-2, 3)(rng)));
  }
  return SparseScores(n, n, -1.0F, std::move(entries));
}

TEST(SparseComponents, AnyOrderAndAnyRanksEqualOneProcessOnPlantedRevisits) {
  std::mt19937 rng(99);
  std::mt19937 shuffle(3);
  for (int trial = 0; trial < 6; ++trial) {
    const std::size_t n = trial < 3 ? 700 : 2500;
    const SparseScores scores = planted_revisits(n, rng);
    align::AlignConfig config;
    config.gap_a = config.gap_b = 1.5F;
    config.cap = trial % 2 == 0 ? std::optional<float>(20.0F) : std::nullopt;
    config.threshold = 8.0F;
    config.self = true;
    config.min_separation = 10;
    const auto expected = sparse_local_alignments_both(scores, config, 2);
    ASSERT_GT(expected.size(), 5U);
    if (n <= 700) {
      ASSERT_EQ(expected, align::local_alignments_both(scores.source(), config, 2));
    }
    const auto components = sparse_components_both(scores, config, 2);
    expect_consistent(scores, config, components);
    for (const std::size_t ranks : {2U, 3U, 5U}) {
      ASSERT_EQ(run_on_ranks(scores, config, components, deal_components(components, ranks), ranks, shuffle), expected)
          << "trial " << trial << ", " << ranks << " ranks";
    }
  }
}

SparseComponent box_of_size(std::size_t cells) {
  SparseComponent c;
  c.box_row_end = cells;
  c.box_col_end = 1;
  return c;
}

TEST(SparseComponents, DealsLargestBoxFirstToTheLeastLoadedRank) {
  // Sizes 5, 9, 9, 1, 4 on two ranks: 9 -> 0, 9 -> 1, 5 -> 0 (tie: lowest rank), 4 -> 1, 1 -> 1.
  const std::vector<SparseComponent> five{box_of_size(5), box_of_size(9), box_of_size(9), box_of_size(1),
                                          box_of_size(4)};
  EXPECT_EQ(deal_components(five, 2), (std::vector<std::size_t>{0, 0, 1, 1, 1}));
  EXPECT_EQ(deal_components(five, 1), (std::vector<std::size_t>(5, 0)));
  // More ranks than components: one each, largest to rank 0.
  EXPECT_EQ(deal_components(five, 7), (std::vector<std::size_t>{2, 0, 1, 4, 3}));
  EXPECT_TRUE(deal_components({}, 3).empty());
  EXPECT_THROW(deal_components(five, 0), std::invalid_argument);

  // Random sizes: every component dealt, and the greedy bound (no rank above the mean by more than the
  // largest box).
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<SparseComponent> boxes;
    const int count = std::uniform_int_distribution<int>(1, 60)(rng);
    std::uniform_int_distribution<std::size_t> size(1, 1000);
    for (int k = 0; k < count; ++k) boxes.push_back(box_of_size(size(rng)));
    const std::size_t ranks = std::uniform_int_distribution<std::size_t>(1, 6)(rng);
    const auto owner = deal_components(boxes, ranks);
    ASSERT_EQ(owner, deal_components(boxes, ranks));
    std::vector<std::size_t> load(ranks, 0);
    std::size_t total = 0, largest = 0;
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      ASSERT_LT(owner[k], ranks);
      load[owner[k]] += boxes[k].box_cells();
      total += boxes[k].box_cells();
      largest = std::max(largest, boxes[k].box_cells());
    }
    EXPECT_LE(*std::max_element(load.begin(), load.end()) * ranks, total + largest * ranks);
  }
}

TEST(SparseComponents, RejectsMismatchedInputs) {
  const SparseScores scores(20, 20, -1.0F, {{15, 2, 5.0F}, {2, 15, 5.0F}});
  align::AlignConfig config;
  config.self = true;
  config.min_separation = 3;
  auto components = sparse_components(scores, config);
  ASSERT_EQ(components.size(), 1U);
  EXPECT_EQ(components[0].kind, SparseBoxKind::inside_band);
  EXPECT_THROW(merge_component_alignments(scores, config, components, {}), std::invalid_argument);
  auto reverse = config;
  reverse.direction = align::Direction::reverse;
  EXPECT_THROW(merge_component_alignments(scores, reverse, components, {{}}), std::invalid_argument);
  components[0].box_row_end = 21;
  EXPECT_THROW(align_component(scores, config, components[0]), std::invalid_argument);
  EXPECT_THROW(sparse_components(SparseScores(4, 4, 0.0F, {}), {}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::scale
