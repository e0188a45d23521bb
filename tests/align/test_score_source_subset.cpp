// ScoreSource::subset against a brute-force gather of the dense matrix: every row segment and cell, through a
// dense source and through a computed one, the memory flag carried over, and bad frame lists refused.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {
namespace {

TEST(ScoreSourceSubset, ReadsTheChosenRowsAndColumnsOfEverySegment) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0F, 2.0F);
  const std::size_t n = 23;
  std::vector<float> values(n * n);
  for (auto& v : values) v = u(rng);
  const ScoreSource dense = ScoreSource::dense(values, n, n);
  const ScoreSource computed =
      ScoreSource::function(n, n, [&](std::size_t i, std::size_t j) { return values[i * n + j]; });
  for (unsigned trial = 0; trial < 20; ++trial) {
    std::vector<std::size_t> frames;
    for (std::size_t f = 0; f < n; ++f) {
      if (rng() % 3 != 0) frames.push_back(f);  // runs of kept frames and single frames left out
    }
    for (const ScoreSource* base : {&dense, &computed}) {
      const ScoreSource view = base->subset(frames);
      ASSERT_EQ(view.rows(), frames.size());
      ASSERT_EQ(view.cols(), frames.size());
      EXPECT_EQ(view.in_memory(), base->in_memory());
      for (std::size_t i = 0; i < frames.size(); ++i) {
        for (std::size_t b = 0; b < frames.size(); ++b) {
          for (std::size_t e = b; e <= frames.size(); ++e) {
            std::vector<float> out(e - b, 99.0F);
            view.read_row(i, b, e, out.data());
            for (std::size_t k = b; k < e; ++k) {
              ASSERT_EQ(out[k - b], values[frames[i] * n + frames[k]]) << i << " " << b << " " << e;
            }
          }
          EXPECT_EQ(view.at(i, b), values[frames[i] * n + frames[b]]);
        }
      }
    }
  }
}

TEST(ScoreSourceSubset, FramesMustAscendWithinTheSource) {
  std::vector<float> values(16, 0.0F);
  const ScoreSource s = ScoreSource::dense(values, 4, 4);
  EXPECT_THROW((void)s.subset({0, 4}), std::invalid_argument);
  EXPECT_THROW((void)s.subset({2, 1}), std::invalid_argument);
  EXPECT_THROW((void)s.subset({1, 1}), std::invalid_argument);
  EXPECT_EQ(s.subset({}).rows(), 0U);
}

}  // namespace
}  // namespace seqtopo::align
