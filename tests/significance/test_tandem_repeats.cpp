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

// The detection written from its definition, each diagonal mean summed afresh for every frame (the library keeps
// running sums): runs of diagonals above the level ahead of or behind the frame at one period and two, closed over
// gaps up to the reach, stretches shorter than min_frames dropped.
std::vector<std::size_t> reference_frames(const SimilarityMatrix& e, const TandemRepeatConfig& c) {
  const std::size_t n = e.rows;
  std::vector<bool> repeat(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = i > c.half_window ? i - c.half_window : 0, hi = std::min(n - 1, i + c.half_window);
    for (const bool ahead : {true, false}) {
      std::vector<bool> alike(c.reach + 2, false);
      for (std::size_t d = c.near + 1; d <= c.reach; ++d) {
        double sum = 0;
        std::size_t count = 0;
        for (std::size_t k = lo; k <= hi; ++k) {
          if (ahead && k + d < n) sum += e(k, k + d), ++count;
          if (!ahead && k >= d) sum += e(k - d, k), ++count;
        }
        alike[d] = count > 0 && sum / static_cast<double>(count) > c.level;
      }
      std::vector<double> centres;
      for (std::size_t d = c.near + 2; d <= c.reach; ++d) {
        if (!alike[d] || alike[d - 1]) continue;
        std::size_t end = d;
        while (end <= c.reach && alike[end]) ++end;
        centres.push_back(0.5 * static_cast<double>(d + end - 1));
      }
      for (std::size_t a = 0; a < centres.size(); ++a) {
        for (std::size_t b = a + 1; b < centres.size(); ++b) {
          if (std::abs(centres[b] - 2 * centres[a]) <= 1.5) repeat[i] = true;
        }
      }
    }
  }
  std::size_t last = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (!repeat[i]) continue;
    if (last != n && i - last <= c.reach)
      std::fill(repeat.begin() + static_cast<long>(last), repeat.begin() + static_cast<long>(i), true);
    last = i;
  }
  std::vector<std::size_t> frames;
  for (std::size_t i = 0; i < n;) {
    std::size_t end = i;
    while (end < n && repeat[end]) ++end;
    if (end - i >= c.min_frames) {
      for (std::size_t k = i; k < end; ++k) frames.push_back(k);
    }
    i = end == i ? i + 1 : end;
  }
  return frames;
}

TEST(TandemRepeats, EqualsTheDefinitionSummedAfreshForEveryFrame) {
  for (unsigned seed = 0; seed < 6; ++seed) {
    std::mt19937 rng(200 + seed);
    std::normal_distribution<double> g(0.0, 1.0);
    const std::size_t n = 250 + 60 * seed, start = 40 + 17 * seed, period = 6;
    Frames x = walk(n, 32, 3.0, rng);
    const Frames door = walk(period, 32, 3.0, rng);
    for (std::size_t i = start; i < start + 130 && i < n; ++i) {
      for (std::size_t d = 0; d < 32; ++d) x[i][d] = 0.8 * door[(i - start) % period][d] + 0.6 * g(rng);
    }
    const SimilarityMatrix e = enhanced(x);
    for (const std::size_t half_window : {2UL, 5UL, 9UL}) {
      TandemRepeatConfig c = config();
      c.half_window = half_window;
      const auto frames = tandem_repeat_frames(e, c);
      EXPECT_EQ(frames, reference_frames(e, c)) << seed << " half window " << half_window;
      if (half_window == 5) {
        EXPECT_GE(frames.size(), 50U) << seed;  // the doors are found: the test sees a repeat
      }
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
