// The engine against the naive full-recomputation reference on thousands of fixed-seed random cases:
// every alignment's score, coordinates and pairs must be identical.
#include <gtest/gtest.h>

#include <random>

#include "random_problems.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

void expect_same(const std::vector<align::LocalAlignment>& got, const std::vector<align::LocalAlignment>& want,
                 int case_id) {
  ASSERT_EQ(got.size(), want.size()) << "case " << case_id;
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].score, want[k].score) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].a_begin, want[k].a_begin) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].a_end, want[k].a_end) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].b_begin, want[k].b_begin) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].b_end, want[k].b_end) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].pairs, want[k].pairs) << "case " << case_id << " alignment " << k;
    EXPECT_EQ(got[k].direction, want[k].direction) << "case " << case_id;
  }
}

TEST(AgainstNaive, RandomSmallProblemsAllAlignments) {
  std::mt19937 rng(20261123);
  int compared_alignments = 0;
  for (int case_id = 0; case_id < 4000; ++case_id) {
    const auto p = test_support::random_problem(rng);
    const auto want = test_support::naive_local_alignments(p.naive);
    const auto got = align::local_alignments(p.source(), p.naive.config);
    expect_same(got, want, case_id);
    compared_alignments += static_cast<int>(want.size());
    if (::testing::Test::HasFailure()) return;
  }
  // The generator must produce real work, or this test proves nothing.
  EXPECT_GT(compared_alignments, 20000);
}

TEST(AgainstNaive, LargerProblemsWithMaxAlignments) {
  std::mt19937 rng(7);
  for (int case_id = 0; case_id < 150; ++case_id) {
    auto p = test_support::random_problem(rng, 70);
    p.naive.config.max_alignments = 1 + case_id % 12;
    expect_same(align::local_alignments(p.source(), p.naive.config), test_support::naive_local_alignments(p.naive),
                case_id);
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(AgainstNaive, CallableSourceEqualsDenseSource) {
  std::mt19937 rng(11);
  for (int case_id = 0; case_id < 300; ++case_id) {
    const auto p = test_support::random_problem(rng);
    const auto callable =
        align::ScoreSource::function(p.rows, p.cols, [&p](std::size_t i, std::size_t j) { return p.naive.s[i][j]; });
    expect_same(align::local_alignments(callable, p.naive.config), align::local_alignments(p.source(), p.naive.config),
                case_id);
  }
}

}  // namespace
}  // namespace seqtopo
