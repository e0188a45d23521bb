// Local contrast enhancement against its definition computed directly, and its invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::similarity {
namespace {

SimilarityMatrix random_matrix(std::size_t rows, std::size_t cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0F, 3.0F);
  SimilarityMatrix m(rows, cols);
  for (auto& v : m.values) v = u(rng);
  return m;
}

TEST(ContrastEnhancement, EqualsDirectDefinition) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    const std::size_t rows = 3 + seed % 7, cols = 5 + seed % 11, window = 1 + seed % 4;
    const auto s = random_matrix(rows, cols, seed);
    const auto e = enhance_contrast(s, window);
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t c = 0; c < cols; ++c) {
        double sum = 0, count = 0;
        for (std::size_t k = 0; k < cols; ++k) {
          if (k + window >= c && k <= c + window) {
            sum += s(r, k);
            count += 1;
          }
        }
        const double mean = sum / count;
        double var = 0;
        for (std::size_t k = 0; k < cols; ++k) {
          if (k + window >= c && k <= c + window) var += (s(r, k) - mean) * (s(r, k) - mean);
        }
        const double expected = (s(r, c) - mean) / std::sqrt(var / count);
        EXPECT_NEAR(e(r, c), expected, 1e-4 * (1 + std::abs(expected))) << r << "," << c;
      }
    }
  }
}

// The header's fixed arithmetic, one cell at a time: the vectorised kernels must give these very bits.
TEST(ContrastEnhancement, BitsOfTheFixedArithmetic) {
  for (unsigned seed = 0; seed < 12; ++seed) {
    const std::size_t rows = 4 + seed % 5, cols = 17 + 13 * seed, window = 1 + (seed * 7) % 23;
    const auto s = random_matrix(rows, cols, 100 + seed);
    const auto e = enhance_contrast(s, window);
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t c = 0; c < cols; ++c) {
        const std::size_t lo = c > window ? c - window : 0, hi = std::min(cols, c + window + 1);
        double sum = 0, sum2 = 0;
        for (std::size_t k = lo; k < hi; ++k) {
          const double x = s(r, k);
          sum += x;
          sum2 += x * x;
        }
        const double count = static_cast<double>(hi - lo), mean = sum / count;
        const double sd = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
        ASSERT_EQ(e(r, c), static_cast<float>((s(r, c) - mean) / std::max(sd, 1e-9))) << seed << ": " << r << "," << c;
      }
    }
  }
}

// Wide windows: the running sums of the header, written out cell by cell (restart at each multiple of the block,
// then add the value entering, subtract the one leaving), give the enhanced bits; and they stay within float
// rounding of the definition computed directly in long double.
TEST(ContrastEnhancement, RunningSumsOfWideWindows) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    const std::size_t cols = 50 + 41 * seed, window = kRunningWindow + (seed * 23) % 130;
    const auto s = random_matrix(2, cols, 500 + seed);
    const auto e = enhance_contrast(s, window);
    for (std::size_t r = 0; r < s.rows; ++r) {
      double sum = 0, sum2 = 0;
      for (std::size_t c = 0; c < cols; ++c) {
        const std::size_t lo = c > window ? c - window : 0, hi = std::min(cols, c + window + 1);
        if (c % kRunningBlock == 0) {
          sum = sum2 = 0;
          for (std::size_t k = lo; k < hi; ++k) {
            const double x = s(r, k);
            sum += x;
            sum2 += x * x;
          }
        } else {
          if (c + window < cols)
            sum += s(r, c + window), sum2 += static_cast<double>(s(r, c + window)) * s(r, c + window);
          if (c > window) {
            const double x = s(r, c - window - 1);
            sum -= x;
            sum2 -= x * x;
          }
        }
        const double count = static_cast<double>(hi - lo), mean = sum / count;
        const double sd = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
        ASSERT_EQ(e(r, c), static_cast<float>((s(r, c) - mean) / std::max(sd, 1e-9))) << seed << ": " << r << "," << c;
        long double m = 0, v = 0;
        for (std::size_t k = lo; k < hi; ++k) m += s(r, k);
        m /= static_cast<long double>(count);
        for (std::size_t k = lo; k < hi; ++k) v += (s(r, k) - m) * (s(r, k) - m);
        const auto direct = static_cast<double>((s(r, c) - m) / std::sqrt(v / static_cast<long double>(count)));
        EXPECT_NEAR(e(r, c), direct, 1e-4 * (1 + std::abs(direct))) << seed << ": " << r << "," << c;
      }
    }
  }
}

// A reader of cells [begin, end) of a row, given only the values from first_read(begin, w) on, gets the bits of the
// whole row's sums, narrow windows and wide.
TEST(ContrastEnhancement, WindowSumsOfAnyPartOfARowAreTheWholeRowsBits) {
  std::mt19937 rng(11);
  for (const std::size_t window : {3UL, 10UL, 31UL, 32UL, 70UL, 400UL}) {
    const std::size_t n = 300;
    const auto s = random_matrix(1, n, static_cast<unsigned>(window));
    std::vector<double> sum(n), sum2(n), count(n);
    window_sums_of(sum.data(), sum2.data(), count.data(), s.values.data(), 0, n, window, 0, n);
    for (int trial = 0; trial < 40; ++trial) {
      const std::size_t b = std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
      const std::size_t e = std::uniform_int_distribution<std::size_t>(b + 1, n)(rng);
      const std::size_t first = first_read(b, window);
      ASSERT_LE(first, b);
      std::vector<float> part(s.values.begin() + static_cast<long>(first),
                              s.values.begin() + static_cast<long>(std::min(n, e + window)));
      std::vector<double> ps(e - b), ps2(e - b), pc(e - b);
      window_sums_of(ps.data(), ps2.data(), pc.data(), part.data(), first, n, window, b, e);
      for (std::size_t c = b; c < e; ++c) {
        ASSERT_EQ(ps[c - b], sum[c]) << window << ": " << b << "-" << e << ", cell " << c;
        ASSERT_EQ(ps2[c - b], sum2[c]) << window << ": " << b << "-" << e << ", cell " << c;
        ASSERT_EQ(pc[c - b], count[c]);
      }
    }
  }
}

TEST(ContrastEnhancement, PrefixIsTheRowsFirstCellsBitForBit) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    const std::size_t cols = 9 + 11 * seed, window = 1 + (seed * 5) % 17;
    const auto s = random_matrix(1, cols, 300 + seed);
    std::vector<float> whole(cols);
    enhance_row(s.values.data(), cols, window, whole.data());
    for (std::size_t end = 0; end <= cols; ++end) {
      std::vector<float> part(cols, -7.0F);
      enhance_row_prefix(s.values.data(), cols, window, end, part.data());
      for (std::size_t c = 0; c < cols; ++c) {
        ASSERT_EQ(part[c], c < end ? whole[c] : -7.0F) << seed << ": end " << end << ", cell " << c;
      }
    }
  }
  std::vector<float> out(4);
  EXPECT_THROW(enhance_row_prefix(out.data(), 4, 1, 5, out.data()), std::invalid_argument);
}

TEST(ContrastEnhancement, WindowSumsDownColumnsInOrder) {
  const auto s = random_matrix(9, 37, 5);  // 37 columns: two blocks of 16 and a tail
  std::vector<double> sum(37), sum2(37);
  window_sums(sum.data(), sum2.data(), s.values.data(), s.cols, s.rows, s.cols);
  for (std::size_t b = 0; b < s.cols; ++b) {
    double a = 0, q = 0;
    for (std::size_t t = 0; t < s.rows; ++t) {
      const double x = s(t, b);
      a += x;
      q += x * x;
    }
    EXPECT_EQ(sum[b], a) << b;
    EXPECT_EQ(sum2[b], q) << b;
  }
}

TEST(ContrastEnhancement, SymmetricFormIsSymmetricAndOffset) {
  const auto s = random_matrix(12, 12, 3);
  const auto e = enhance_contrast(s, 3);
  const auto sym = enhance_contrast_symmetric(s, 3, 0.75F);
  for (std::size_t i = 0; i < 12; ++i) {
    for (std::size_t j = 0; j < 12; ++j) {
      EXPECT_EQ(sym(i, j), sym(j, i));
      EXPECT_FLOAT_EQ(sym(i, j), 0.5F * (e(i, j) + e(j, i)) - 0.75F);
    }
  }
  EXPECT_THROW(enhance_contrast_symmetric(random_matrix(3, 4, 1), 2, 0.0F), std::invalid_argument);
}

TEST(ContrastEnhancement, InvariantToAffineChangesOfARow) {
  // A row scaled and shifted (a frame that is uniformly brighter) enhances to the same values.
  auto s = random_matrix(4, 20, 9);
  const auto before = enhance_contrast(s, 5);
  for (auto& v : s.row(2)) v = 3.0F * v + 7.0F;
  const auto after = enhance_contrast(s, 5);
  for (std::size_t c = 0; c < 20; ++c) EXPECT_NEAR(after(2, c), before(2, c), 1e-4);
  EXPECT_EQ(enhance_contrast(s, 0), s) << "window 0 leaves the matrix as it is";
}

}  // namespace
}  // namespace seqtopo::similarity
