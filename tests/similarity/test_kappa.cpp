// kappa auto and S = 1 - kappa * D.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "seqtopo/similarity/similarity_from_distance.hpp"

namespace seqtopo::similarity {
namespace {

DenseMatrix<float> random_symmetric(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<float> u(0.1F, 2.0F);
  DenseMatrix<float> d(n, n, 0.0F);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) d(i, j) = d(j, i) = u(rng);
  }
  return d;
}

TEST(Kappa, AutoGivesSPositiveToTheChosenFractionOfCandidatePairs) {
  std::mt19937 rng(31);
  const std::size_t n = 400;
  const auto d = random_symmetric(rng, n);
  const KappaRule rule;
  const auto choice = choose_kappa(d, true, rule);
  EXPECT_NEAR(choice.fraction, rule.matches_per_image / static_cast<double>(n - rule.min_separation), 1e-12);
  const auto s = similarity_from_distance(d, choice.kappa);
  std::size_t positive = 0, candidates = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j + rule.min_separation <= i; ++j) {
      ++candidates;
      positive += s(i, j) > 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(candidates, choice.candidates);
  EXPECT_NEAR(static_cast<double>(positive) / static_cast<double>(candidates), choice.fraction, 0.002);
}

TEST(Kappa, NeighboursDoNotUseUpTheQuantile) {
  // Neighbouring frames are much closer than anything else; the rule must look past them.
  std::mt19937 rng(32);
  auto d = random_symmetric(rng, 200);
  for (std::size_t i = 1; i < 200; ++i) d(i, i - 1) = d(i - 1, i) = 0.001F;
  const auto choice = choose_kappa(d, true);
  EXPECT_GT(choice.quantile, 0.1);
}

TEST(Kappa, RectangularUsesEveryCell) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  DenseMatrix<float> d(100, 250);
  for (auto& v : d.values) v = u(rng);
  const auto choice = choose_kappa(d, false);
  EXPECT_EQ(choice.candidates, 100U * 250U);
  EXPECT_NEAR(choice.fraction, 5.0 / 250.0, 1e-12);
  EXPECT_NEAR(choice.quantile, choice.fraction, 0.01);  // uniform distances: the p-quantile is about p
}

TEST(Kappa, DegenerateInputs) {
  EXPECT_EQ(choose_kappa(DenseMatrix<float>(1, 1, 0.0F), true).kappa, 1.0F);
  EXPECT_EQ(choose_kappa(DenseMatrix<float>(3, 3, 0.0F), true).kappa, 1.0F);  // all identical
  DenseMatrix<float> small(3, 3, 0.5F);
  EXPECT_FLOAT_EQ(choose_kappa(small, true).kappa, 2.0F);
  EXPECT_THROW(choose_kappa(DenseMatrix<float>(2, 3), true), std::invalid_argument);
}

TEST(Similarity, LinearTransform) {
  const DenseMatrix<float> d(1, 3, std::vector<float>{0.0F, 0.5F, 2.0F});
  const auto s = similarity_from_distance(d, 2.0F);
  EXPECT_EQ(s.values, (std::vector<float>{1.0F, 0.0F, -3.0F}));
  EXPECT_THROW(similarity_from_distance(d, 0.0F), std::invalid_argument);
  EXPECT_THROW(similarity_from_distance(d, std::nanf("")), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::similarity
