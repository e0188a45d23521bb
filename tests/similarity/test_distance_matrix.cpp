// The tiled multi-threaded matrix against the pairwise functions, and its invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/similarity/distance_matrix.hpp"
#include "seqtopo/similarity/memory.hpp"

namespace seqtopo::similarity {
namespace {

std::vector<SparseHistogram> random_histograms(std::mt19937& rng, std::size_t n, std::size_t bins) {
  std::vector<SparseHistogram> out;
  std::uniform_real_distribution<float> value(0.0F, 1.0F);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<float> h(bins, 0.0F);
    const double fill = (rng() % 50) / 100.0;
    for (auto& v : h) {
      if (value(rng) < fill) v = value(rng) + 0.001F;
    }
    out.push_back(SparseHistogram::from_dense(h));
  }
  return out;
}

DenseMatrix<float> random_rows(std::mt19937& rng, std::size_t n, std::size_t d, bool positive) {
  std::normal_distribution<float> g(0.0F, 1.0F);
  DenseMatrix<float> m(n, d);
  for (auto& v : m.values) v = positive ? std::fabs(g(rng)) : g(rng);
  return m;
}

TEST(DistanceMatrix, SparseCellsEqualPairwiseFunction) {
  std::mt19937 rng(21);
  const auto set = DescriptorSet::from_sparse(random_histograms(rng, 37, 300));
  for (Distance m : {Distance::chi2, Distance::l1, Distance::cosine, Distance::sad}) {
    const auto d = distance_matrix(set, m, {.threads = 2, .tile = 8, .progress = {}});
    ASSERT_EQ(d.rows, 37U);
    for (std::size_t i = 0; i < d.rows; ++i) {
      EXPECT_EQ(d(i, i), 0.0F);
      for (std::size_t j = 0; j < i; ++j) {
        EXPECT_EQ(d(i, j), static_cast<float>(distance(m, set.sparse[i], set.sparse[j]))) << i << "," << j;
        EXPECT_EQ(d(i, j), d(j, i));
      }
    }
  }
}

TEST(DistanceMatrix, DenseRectangularCellsEqualPairwiseFunction) {
  std::mt19937 rng(22);
  const auto a = DescriptorSet::from_dense(random_rows(rng, 19, 33, true));
  const auto b = DescriptorSet::from_dense(random_rows(rng, 26, 33, true));
  for (Distance m : {Distance::chi2, Distance::l1, Distance::cosine, Distance::sad}) {
    const auto d = distance_matrix(a, b, m, {.threads = 3, .tile = 5, .progress = {}});
    ASSERT_EQ(d.rows, 19U);
    ASSERT_EQ(d.cols, 26U);
    for (std::size_t i = 0; i < d.rows; ++i) {
      for (std::size_t j = 0; j < d.cols; ++j) {
        EXPECT_EQ(d(i, j), static_cast<float>(distance(m, a.dense.row(i), b.dense.row(j))));
      }
    }
  }
}

// Values q * 2^-shift with |q| <= 127 (as patch thumbnails are): the matrix compares them in byte lanes.
DenseMatrix<float> grid_rows(std::mt19937& rng, std::size_t n, std::size_t d, int shift) {
  std::uniform_int_distribution<int> q(-127, 127);
  DenseMatrix<float> m(n, d);
  for (auto& v : m.values) v = std::ldexp(static_cast<float>(q(rng)), -shift);
  if (!m.values.empty()) m.values.front() = std::ldexp(127.0F, -shift), m.values.back() = std::ldexp(-127.0F, -shift);
  return m;
}

TEST(DistanceMatrix, ByteGridCellsEqualThePairwiseFloatFunction) {
  std::mt19937 rng(24);
  for (const std::size_t dim : {1UL, 31UL, 32UL, 33UL, 70UL, 2048UL}) {
    for (const int shift : {0, 4, 7}) {
      const auto set = DescriptorSet::from_dense(grid_rows(rng, 23, dim, shift));
      for (Distance m : {Distance::l1, Distance::sad}) {
        const auto d = distance_matrix(set, m, {.threads = 2, .tile = 6, .progress = {}});
        for (std::size_t i = 0; i < d.rows; ++i) {
          for (std::size_t j = 0; j < d.cols; ++j) {
            // Brute force in double, independent of both kernels: exact on the grid.
            double l1 = 0;
            for (std::size_t k = 0; k < dim; ++k)
              l1 += std::fabs(static_cast<double>(set.dense(i, k)) - static_cast<double>(set.dense(j, k)));
            const double expected = m == Distance::sad ? l1 / static_cast<double>(dim) : l1;
            ASSERT_EQ(d(i, j), static_cast<float>(expected)) << dim << " " << shift << ": " << i << "," << j;
            ASSERT_EQ(d(i, j), static_cast<float>(distance(m, set.dense.row(i), set.dense.row(j))));
          }
        }
      }
    }
  }
}

TEST(DistanceMatrix, ByteGridOfTwoSetsTakesTheFinerStep) {
  std::mt19937 rng(25);
  auto a = DescriptorSet::from_dense(grid_rows(rng, 9, 45, 1));
  for (auto& v : a.dense.values) v = std::clamp(v, -31.0F, 31.0F);  // within +-31.75: also on the 2^-2 grid
  auto b = DescriptorSet::from_dense(grid_rows(rng, 13, 45, 2));
  auto off = b;  // one value off every grid: the float kernel, the same cells
  off.dense.values[5] += 1e-3F;
  for (const DescriptorSet* other : {&b, &off}) {
    const auto d = distance_matrix(a, *other, Distance::sad, {.threads = 2, .tile = 4, .progress = {}});
    for (std::size_t i = 0; i < d.rows; ++i) {
      for (std::size_t j = 0; j < d.cols; ++j)
        ASSERT_EQ(d(i, j), static_cast<float>(distance(Distance::sad, a.dense.row(i), other->dense.row(j))));
    }
  }
}

TEST(DistanceMatrix, BitIdenticalForAnyThreadCountAndTile) {
  std::mt19937 rng(23);
  const auto sparse = DescriptorSet::from_sparse(random_histograms(rng, 150, 500));
  const auto dense = DescriptorSet::from_dense(random_rows(rng, 90, 64, false));
  const auto ref_sparse = distance_matrix(sparse, Distance::chi2, {.threads = 1, .tile = 64, .progress = {}});
  const auto ref_dense = distance_matrix(dense, Distance::cosine, {.threads = 1, .tile = 64, .progress = {}});
  for (unsigned threads : {2U, 3U, 8U}) {
    for (std::size_t tile : {1U, 7U, 32U, 1000U}) {
      EXPECT_EQ(distance_matrix(sparse, Distance::chi2, {.threads = threads, .tile = tile, .progress = {}}),
                ref_sparse);
      EXPECT_EQ(distance_matrix(dense, Distance::cosine, {.threads = threads, .tile = tile, .progress = {}}),
                ref_dense);
    }
  }
}

TEST(DistanceMatrix, RectangularOfASetWithItselfAgreesWithSymmetric) {
  std::mt19937 rng(24);
  const auto set = DescriptorSet::from_sparse(random_histograms(rng, 40, 200));
  const auto sym = distance_matrix(set, Distance::chi2);
  const auto full = distance_matrix(set, set, Distance::chi2);
  for (std::size_t i = 0; i < sym.rows; ++i) {
    EXPECT_EQ(full(i, i), 0.0F);
    for (std::size_t j = 0; j < sym.cols; ++j) EXPECT_NEAR(full(i, j), sym(i, j), 1e-6F * (1.0F + sym(i, j)));
  }
}

TEST(DistanceMatrix, ProgressReachesTotal) {
  std::mt19937 rng(25);
  const auto set = DescriptorSet::from_dense(random_rows(rng, 50, 8, false));
  std::size_t last = 0, total = 0, calls = 0;
  MatrixConfig config{.threads = 2, .tile = 16, .progress = [&](std::size_t done, std::size_t all) {
                        EXPECT_GT(done, last);
                        last = done;
                        total = all;
                        ++calls;
                      }};
  distance_matrix(set, Distance::l1, config);
  EXPECT_EQ(total, 50U * 49U / 2U);
  EXPECT_EQ(last, total);
  EXPECT_GT(calls, 1U);
}

TEST(DistanceMatrix, MisuseThrows) {
  std::mt19937 rng(26);
  const auto signed_rows = DescriptorSet::from_dense(random_rows(rng, 4, 3, false));
  EXPECT_THROW(distance_matrix(signed_rows, Distance::chi2), std::invalid_argument);
  const auto other = DescriptorSet::from_dense(random_rows(rng, 4, 5, true));
  EXPECT_THROW(distance_matrix(signed_rows, other, Distance::l1), std::invalid_argument);
  const auto sparse = DescriptorSet::from_sparse(random_histograms(rng, 3, 10));
  EXPECT_THROW(distance_matrix(sparse, other, Distance::l1), std::invalid_argument);
  EXPECT_THROW(distance_matrix(sparse, Distance::l1, {.threads = 1, .tile = 0, .progress = {}}), std::invalid_argument);
  EXPECT_EQ(distance_matrix(DescriptorSet{}, Distance::l1).rows, 0U);
}

TEST(Memory, EstimateAndRefusal) {
  EXPECT_EQ(matrix_bytes(1800, 1800), 1800U * 1800U * 4U);
  EXPECT_EQ(matrix_bytes(std::numeric_limits<std::size_t>::max() / 2, 3), std::numeric_limits<std::size_t>::max());
  EXPECT_NO_THROW(check_fits(100, 1000, "x"));
  EXPECT_NO_THROW(check_fits(100, std::nullopt, "x"));
  try {
    check_fits(std::size_t{3} << 30U, std::size_t{1} << 30U, "the matrix");
    FAIL() << "expected a refusal";
  } catch (const MemoryError& e) {
    EXPECT_NE(std::string(e.what()).find("the matrix needs 3.0 GiB, only 1.0 GiB"), std::string::npos) << e.what();
  }
  EXPECT_THROW(check_fits(std::numeric_limits<std::size_t>::max(), std::nullopt, "x"), MemoryError);
  EXPECT_EQ(format_bytes(1536), "1.5 KiB");
  // The matrix is refused before it is allocated when its budget is smaller; no budget, no check.
  const DescriptorSet rows = DescriptorSet::from_dense(DenseMatrix<float>(100, 4, 1.0F));
  EXPECT_THROW(distance_matrix(rows, Distance::l1, {.memory_budget = matrix_bytes(100, 100) - 1}), MemoryError);
  EXPECT_EQ(distance_matrix(rows, Distance::l1, {.memory_budget = matrix_bytes(100, 100)}).rows, 100U);
  EXPECT_EQ(distance_matrix(rows, Distance::l1).rows, 100U);
}

}  // namespace
}  // namespace seqtopo::similarity
