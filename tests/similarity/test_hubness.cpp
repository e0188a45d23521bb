// similarity/hubness.hpp against a direct computation: r(i) the mean of row i's k highest values at least
// min_separation away, and S'(i, j) = S(i, j) - (r(i) + r(j)) / 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <stdexcept>

#include "seqtopo/similarity/hubness.hpp"

namespace seqtopo::similarity {
namespace {

SimilarityMatrix random_symmetric(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, 1.0F);
  SimilarityMatrix s(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) s(i, j) = s(j, i) = g(rng);
  }
  return s;
}

TEST(Hubness, NeighbourhoodSimilarityIsTheMeanOfTheKHighestFarCells) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const SimilarityMatrix s = random_symmetric(37, seed);
    for (std::size_t k : {1U, 4U, 10U, 100U}) {
      const std::size_t sep = seed;  // 1 .. 5
      const std::vector<float> r = neighbourhood_similarity(s, k, sep);
      for (std::size_t i = 0; i < s.rows; ++i) {
        std::vector<double> far;
        for (std::size_t j = 0; j < s.cols; ++j) {
          if ((i > j ? i - j : j - i) >= sep) far.push_back(s(i, j));
        }
        std::sort(far.begin(), far.end(), std::greater<>());
        far.resize(std::min(k, far.size()));
        double mean = 0;
        for (double v : far) mean += v / static_cast<double>(far.size());
        EXPECT_NEAR(r[i], mean, 1e-5) << "row " << i << " k " << k;
      }
    }
  }
}

TEST(Hubness, AHubStopsStandingOutAndTheCorrectionIsTheFormula) {
  // Frames 10-19 all alike (a tunnel): their cells are high everywhere among themselves.
  SimilarityMatrix s = random_symmetric(60, 9);
  for (std::size_t i = 10; i < 20; ++i) {
    for (std::size_t j = 10; j < 20; ++j) s(i, j) = 5.0F;
  }
  const std::vector<float> r = neighbourhood_similarity(s, 3, 2);
  SimilarityMatrix c = s;
  correct_hubness(c, 3, 2);
  for (std::size_t i = 0; i < 60; ++i) {
    for (std::size_t j = 0; j < 60; ++j) EXPECT_NEAR(c(i, j), s(i, j) - 0.5 * (r[i] + r[j]), 1e-5);
  }
  EXPECT_NEAR(c(10, 15), 0.0F, 1e-5);  // as alike as each is to its 3 most similar frames: no evidence
  EXPECT_GT(r[12], r[40]);
  SimilarityMatrix unchanged = s;
  correct_hubness(unchanged, 0, 2);
  EXPECT_EQ(unchanged, s);
  EXPECT_THROW(neighbourhood_similarity(SimilarityMatrix(2, 3), 3, 1), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::similarity
