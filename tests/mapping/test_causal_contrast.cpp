// Causal contrast enhancement against a brute-force reference: the z-score of each score in its row window (the
// past only) and in its column's last w + 1 rows, averaged; several similarities each enhanced and then averaged;
// and the offline enhancement of the whole matrix where the windows see the same cells.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/mapping/causal_contrast.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::mapping {
namespace {

// Population z-score of v among `cells`, in double.
double z(double v, const std::vector<double>& cells) {
  double mean = 0;
  for (const double c : cells) mean += c;
  mean /= static_cast<double>(cells.size());
  double var = 0;
  for (const double c : cells) var += (c - mean) * (c - mean);
  const double sd = std::sqrt(var / static_cast<double>(cells.size()));
  return (v - mean) / std::max(sd, 1e-9);
}

// S(t, j) for j < t of a symmetric random similarity.
SimilarityMatrix random_similarity(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g;
  SimilarityMatrix s(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) s(i, j) = s(j, i) = g(rng);
  }
  return s;
}

double reference(const std::vector<SimilarityMatrix>& ss, std::size_t t, std::size_t j, std::size_t w) {
  double fused = 0;
  for (const auto& s : ss) {
    std::vector<double> row, column;
    for (std::size_t k = j >= w ? j - w : 0; k <= std::min(t - 1, j + w); ++k) row.push_back(s(t, k));
    for (std::size_t r = std::max(t >= w ? t - w : 0, j + 1); r <= t; ++r) column.push_back(s(r, j));
    fused += 0.5 * (z(s(t, j), row) + z(s(t, j), column));
  }
  return fused / static_cast<double>(ss.size());
}

TEST(CausalContrast, EachScoreIsItsRowAndColumnZScoresOverThePast) {
  for (const std::size_t channels : {1U, 2U}) {
    std::vector<SimilarityMatrix> ss;
    for (std::size_t c = 0; c < channels; ++c) ss.push_back(random_similarity(40, static_cast<unsigned>(7 + c)));
    for (const std::size_t w : {1U, 3U, 10U}) {
      CausalContrast contrast(w);
      std::vector<float> out;
      for (std::size_t t = 0; t < 40; ++t) {
        std::vector<std::span<const float>> rows;
        for (const auto& s : ss) rows.emplace_back(s.values.data() + t * s.cols, t);
        const std::size_t n = t >= 2 ? t - 2 : 0;  // the columns of a self search with min_separation 3
        contrast.add(rows, n, out);
        ASSERT_EQ(out.size(), n);
        for (std::size_t j = 0; j < n; ++j) {
          ASSERT_NEAR(out[j], reference(ss, t, j, w), 2e-4) << "channels " << channels << " w " << w << " t " << t;
        }
      }
      EXPECT_EQ(contrast.rows(), 40U);
    }
  }
}

TEST(CausalContrast, ARowWindowOfThePastIsTheOfflineRowEnhancement) {
  // The row part alone, where the offline window sees no future column (j + w < t): the offline enhance_row of the
  // row's first t values, to the bit.
  const auto s = random_similarity(30, 3);
  const std::size_t w = 4;
  CausalContrast contrast(w);
  std::vector<float> out, offline(30);
  for (std::size_t t = 0; t < 30; ++t) {
    contrast.add({std::span<const float>(s.values.data() + t * s.cols, t)}, t, out);
    if (t < 2) continue;
    similarity::enhance_row(s.values.data() + t * s.cols, t, w, offline.data());
    for (std::size_t j = 0; j + w < t; ++j) {
      std::vector<double> column;
      for (std::size_t r = std::max(t >= w ? t - w : 0, j + 1); r <= t; ++r) column.push_back(s(r, j));
      EXPECT_NEAR(out[j], 0.5 * (offline[j] + z(s(t, j), column)), 2e-4) << t << " " << j;
    }
  }
}

TEST(CausalContrast, NoWindowAveragesTheRowsAndBadRowsAreRefused) {
  const auto a = random_similarity(10, 1), b = random_similarity(10, 2);
  CausalContrast none(0);
  std::vector<float> out;
  for (std::size_t t = 0; t < 10; ++t) {
    none.add({std::span<const float>(a.values.data() + t * 10, t), std::span<const float>(b.values.data() + t * 10, t)},
             t, out);
    for (std::size_t j = 0; j < t; ++j) EXPECT_FLOAT_EQ(out[j], a(t, j) / 2 + b(t, j) / 2);
  }
  CausalContrast c(3);
  EXPECT_THROW(c.add({std::span<const float>(a.values.data(), 2)}, 0, out), std::invalid_argument);  // row 0 is empty
  EXPECT_THROW(c.add({std::span<const float>(a.values.data(), 0)}, 1, out), std::invalid_argument);  // n > t
}

}  // namespace
}  // namespace seqtopo::mapping
