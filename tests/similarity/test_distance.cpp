// The distances against slow, literal implementations of their definitions, on fixed-seed random inputs.
// The fast kernels compute each term in float (the precision of the stored histograms) and sum in double,
// hence the tolerances of a few float roundings.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "seqtopo/similarity/distance.hpp"
#include "seqtopo/similarity/sparse_histogram.hpp"

namespace seqtopo::similarity {
namespace {

// Paper eq. (1), bin by bin over the dense histograms, 0/0 terms skipped.
double reference_chi2(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double x = a[k], y = b[k];
    if (x + y == 0) continue;
    d += (x - y) * (x - y) / (x + y);
  }
  return d;
}

double reference_l1(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d += std::fabs(static_cast<double>(a[k]) - b[k]);
  return d;
}

double reference_cosine(const std::vector<float>& a, const std::vector<float>& b) {
  double ab = 0, aa = 0, bb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ab += static_cast<double>(a[k]) * b[k];
    aa += static_cast<double>(a[k]) * a[k];
    bb += static_cast<double>(b[k]) * b[k];
  }
  if (aa == 0 && bb == 0) return 0;
  if (aa == 0 || bb == 0) return 1;
  return 1 - ab / std::sqrt(aa * bb);
}

// A normalised histogram with about `fill` of its bins non-empty.
std::vector<float> random_histogram(std::mt19937& rng, std::size_t bins, double fill) {
  std::bernoulli_distribution used(fill);
  std::uniform_real_distribution<float> value(0.01F, 1.0F);
  std::vector<float> h(bins, 0.0F);
  double sum = 0;
  for (auto& v : h) {
    if (used(rng)) {
      v = value(rng);
      sum += v;
    }
  }
  if (sum > 0) {
    for (auto& v : h) v = static_cast<float>(v / sum);
  }
  return h;
}

TEST(Distance, SparseChi2MatchesDenseReference) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t bins = 1 + rng() % 400;
    const double fill_a = (rng() % 100) / 100.0, fill_b = (rng() % 100) / 100.0;
    const auto a = random_histogram(rng, bins, fill_a);
    const auto b = random_histogram(rng, bins, fill_b);
    const auto sa = SparseHistogram::from_dense(a), sb = SparseHistogram::from_dense(b);
    const double expected = reference_chi2(a, b);
    EXPECT_NEAR(chi2_distance(sa, sb), expected, 1e-7 + 1e-6 * expected) << "trial " << trial;
    EXPECT_NEAR(chi2_distance(a, b), expected, 1e-7 + 1e-6 * expected) << "trial " << trial;
  }
}

TEST(Distance, SparseL1SadCosineMatchDenseReference) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t bins = 1 + rng() % 300;
    const auto a = random_histogram(rng, bins, (rng() % 100) / 100.0);
    const auto b = random_histogram(rng, bins, (rng() % 100) / 100.0);
    const auto sa = SparseHistogram::from_dense(a), sb = SparseHistogram::from_dense(b);
    EXPECT_NEAR(distance(Distance::l1, sa, sb), reference_l1(a, b), 1e-6);
    EXPECT_NEAR(distance(Distance::l1, a, b), reference_l1(a, b), 1e-6);
    EXPECT_NEAR(distance(Distance::sad, sa, sb), reference_l1(a, b) / static_cast<double>(bins), 1e-6);
    EXPECT_NEAR(distance(Distance::cosine, sa, sb), reference_cosine(a, b), 1e-6);
    EXPECT_NEAR(distance(Distance::cosine, a, b), reference_cosine(a, b), 1e-6);
  }
}

TEST(Distance, ZeroSelfDistanceExactly) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 100; ++trial) {
    const auto a = random_histogram(rng, 1 + rng() % 500, 0.3);
    const auto sa = SparseHistogram::from_dense(a);
    for (Distance m : {Distance::chi2, Distance::l1, Distance::cosine, Distance::sad}) {
      EXPECT_EQ(distance(m, sa, sa), 0.0) << distance_name(m);
      EXPECT_EQ(distance(m, std::span<const float>(a), std::span<const float>(a)), 0.0) << distance_name(m);
    }
  }
}

TEST(Distance, SymmetricAndNonNegative) {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t bins = 1 + rng() % 200;
    const auto a = random_histogram(rng, bins, 0.4), b = random_histogram(rng, bins, 0.2);
    const auto sa = SparseHistogram::from_dense(a), sb = SparseHistogram::from_dense(b);
    for (Distance m : {Distance::chi2, Distance::l1, Distance::cosine, Distance::sad}) {
      const double ab = distance(m, sa, sb), ba = distance(m, sb, sa);
      EXPECT_GE(ab, 0.0);
      EXPECT_NEAR(ab, ba, 1e-6 * (1 + ab)) << distance_name(m);
    }
  }
}

TEST(Distance, Chi2OfDisjointNormalisedHistogramsIsTwo) {
  const std::vector<float> a{0.5F, 0.5F, 0, 0}, b{0, 0, 0.25F, 0.75F};
  EXPECT_DOUBLE_EQ(chi2_distance(SparseHistogram::from_dense(a), SparseHistogram::from_dense(b)), 2.0);
  EXPECT_DOUBLE_EQ(chi2_distance(a, b), 2.0);
}

TEST(Distance, DenseCosineOfSignedVectors) {
  const std::vector<float> a{1, -2, 3}, b{-1, 2, -3}, zero{0, 0, 0};
  EXPECT_NEAR(cosine_distance(a, b), 2.0, 1e-9);
  EXPECT_EQ(cosine_distance(a, zero), 1.0);
  EXPECT_EQ(cosine_distance(zero, zero), 0.0);
}

TEST(Distance, MisuseThrows) {
  const std::vector<float> a{1, 2}, b{1, 2, 3};
  EXPECT_THROW(distance(Distance::l1, a, b), std::invalid_argument);
  SparseHistogram x = SparseHistogram::from_dense(std::vector<float>{1, 0});
  SparseHistogram y = SparseHistogram::from_dense(std::vector<float>{1, 0, 0});
  EXPECT_THROW(chi2_distance(x, y), std::invalid_argument);
  EXPECT_THROW(SparseHistogram::from_dense(std::vector<float>{1, -1}), std::invalid_argument);
  EXPECT_THROW(parse_distance("euclid"), std::invalid_argument);
  EXPECT_EQ(parse_distance("sad"), Distance::sad);
}

TEST(SparseHistogram, RoundTripAndValidation) {
  const std::vector<float> dense{0, 0.25F, 0, 0.75F, 0};
  const auto h = SparseHistogram::from_dense(dense);
  EXPECT_EQ(h.nonzeros(), 2U);
  EXPECT_EQ(h.bins, (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(h.to_dense(), dense);
  EXPECT_NO_THROW(h.validate());
  SparseHistogram bad = h;
  bad.bins = {3, 1};
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad.bins = {1, 5};
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::similarity
