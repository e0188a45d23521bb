// significance/tandem_repeats.hpp: frames of a periodic stretch (a corridor of identical doors) are found, and a
// smooth walk, a stop, a U-turn and a revisit from farther than the reach are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "seqtopo/significance/tandem_repeats.hpp"

namespace seqtopo::significance {
namespace {

using Frames = std::vector<std::vector<double>>;

// AR(1) descriptors alike over about `corr` frames.
Frames walk(std::size_t n, std::size_t dim, double corr, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const double rho = std::exp(-1.0 / corr);
  Frames x(n, std::vector<double>(dim));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t d = 0; d < dim; ++d) x[i][d] = (i ? rho * x[i - 1][d] : 0.0) + std::sqrt(1 - rho * rho) * g(rng);
  }
  return x;
}

// Cosine similarity, each cell's z-score against its row within +-window, symmetrised: the map's contrast
// enhancement, written here from its definition.
SimilarityMatrix enhanced(const Frames& x, std::size_t window = 18) {
  const std::size_t n = x.size();
  std::vector<double> s(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      double ab = 0, aa = 0, bb = 0;
      for (std::size_t d = 0; d < x[i].size(); ++d)
        ab += x[i][d] * x[j][d], aa += x[i][d] * x[i][d], bb += x[j][d] * x[j][d];
      s[i * n + j] = ab / std::sqrt(aa * bb);
    }
  }
  std::vector<double> z(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t lo = j > window ? j - window : 0, hi = std::min(n, j + window + 1);
      double sum = 0, sum2 = 0;
      for (std::size_t k = lo; k < hi; ++k) sum += s[i * n + k], sum2 += s[i * n + k] * s[i * n + k];
      const double m = static_cast<double>(hi - lo), mean = sum / m;
      const double sd = std::sqrt(std::max(sum2 / m - mean * mean, 1e-12));
      z[i * n + j] = (s[i * n + j] - mean) / sd;
    }
  }
  SimilarityMatrix e(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) e(i, j) = static_cast<float>(0.5 * (z[i * n + j] + z[j * n + i]));
  }
  return e;
}

TandemRepeatConfig config() {
  TandemRepeatConfig c;
  c.near = 4;
  c.reach = 18;
  c.min_frames = 18;
  return c;
}

TEST(TandemRepeats, ACorridorOfIdenticalDoorsIsFoundAndNothingElse) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    Frames x = walk(400, 32, 3.0, rng);
    const Frames door = walk(6, 32, 3.0, rng);  // a 6-frame door, passed 20 times
    for (std::size_t i = 150; i < 270; ++i) {
      for (std::size_t d = 0; d < 32; ++d) x[i][d] = 0.8 * door[(i - 150) % 6][d] + 0.6 * g(rng);
    }
    const auto frames = tandem_repeat_frames(enhanced(x), config());
    std::size_t inside = 0, outside = 0;
    for (std::size_t f : frames) (f >= 150 && f < 270 ? inside : outside) += 1;
    EXPECT_GE(inside, 50U) << seed;  // most of it where the noise lets the period show (the map needs no more)
    EXPECT_LE(outside, 6U) << seed;  // at most the stretch's edges
  }
}

TEST(TandemRepeats, ASmoothWalkAStopAUTurnAndARevisitAreNotRepeats) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    std::mt19937 rng(100 + seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (const double corr : {3.0, 10.0}) {
      Frames x = walk(400, 32, corr, rng);
      for (std::size_t i = 100; i < 130; ++i) {  // a stop: 30 frames of one place, with sensor noise
        for (std::size_t d = 0; d < 32; ++d) x[i][d] = x[99][d] + 0.3 * g(rng);
      }
      for (std::size_t i = 200; i < 240; ++i) x[i] = x[399 - i];  // a U-turn at 199.5 walks back over 160-199
      for (std::size_t i = 300; i < 360; ++i) {                   // a revisit of frames 20-79
        for (std::size_t d = 0; d < 32; ++d) x[i][d] = x[i - 280][d] + 0.5 * g(rng);
      }
      EXPECT_TRUE(tandem_repeat_frames(enhanced(x), config()).empty()) << seed << " corr " << corr;
    }
  }
}

TEST(TandemRepeats, RefusesBadSettings) {
  const SimilarityMatrix square(5, 5, 0.0F);
  TandemRepeatConfig c;
  c.near = 10;
  c.reach = 10;
  EXPECT_THROW(tandem_repeat_frames(square, c), std::invalid_argument);
  EXPECT_THROW(tandem_repeat_frames(SimilarityMatrix(4, 5, 0.0F)), std::invalid_argument);
  TandemRepeatConfig flat;
  flat.level = 0;
  EXPECT_THROW(tandem_repeat_frames(square, flat), std::invalid_argument);
  EXPECT_TRUE(tandem_repeat_frames(SimilarityMatrix(0, 0)).empty());
}

}  // namespace
}  // namespace seqtopo::significance
