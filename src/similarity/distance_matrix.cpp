#include "seqtopo/similarity/distance_matrix.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "kernels.hpp"
#include "seqtopo/similarity/memory.hpp"

namespace seqtopo::similarity {

DescriptorSet DescriptorSet::from_dense(DenseMatrix<float> rows) {
  DescriptorSet set;
  set.dense = std::move(rows);
  return set;
}

DescriptorSet DescriptorSet::from_sparse(std::vector<SparseHistogram> histograms) {
  DescriptorSet set;
  set.sparse = std::move(histograms);
  return set;
}

std::size_t DescriptorSet::dimension() const { return is_sparse() ? sparse.front().dimension : dense.cols; }

std::size_t DescriptorSet::memory_bytes() const {
  std::size_t bytes = dense.values.size() * sizeof(float);
  for (const auto& h : sparse) bytes += sizeof(h) + h.bins.size() * (sizeof(std::uint32_t) + sizeof(float));
  return bytes;
}

namespace {

// Per-item quantities the kernels need besides the item itself.
struct Prepared {
  std::vector<double> sum;    // sparse: sum of the values (chi2, L1)
  std::vector<double> norm2;  // sum of squares (cosine)
  // Sparse: each histogram's bins renumbered among the bins that either sequence uses (in the same order),
  // so the eight scattered rows take (used bins) x 8 floats instead of (all bins) x 8: a few hundred KB that
  // stay in cache instead of 655 KB that do not (20,480 joint-histogram bins, a few thousand used).
  std::vector<std::uint32_t> compact_bins;
  std::vector<std::size_t> compact_begin;  // item i's bins: compact_bins[compact_begin[i] .. compact_begin[i + 1])
  // Dense on a byte grid (kernels.hpp): the rows as bytes, and the grid step.
  std::vector<std::uint8_t> bytes;
  double step = 0;
};

// The smallest shift on whose byte grid every value of both sets lies, or -1.
int common_byte_grid(const DescriptorSet& a, const DescriptorSet& b) {
  for (int shift = 0; shift <= 7; ++shift) {
    if (detail::on_byte_grid(a.dense.values.data(), a.dense.values.size(), shift) &&
        (&a == &b || detail::on_byte_grid(b.dense.values.data(), b.dense.values.size(), shift)))
      return shift;
  }
  return -1;
}

void prepare_bytes(const DescriptorSet& set, int shift, Prepared& p) {
  p.bytes.resize(set.dense.values.size());
  detail::to_bytes(set.dense.values.data(), set.dense.values.size(), shift, p.bytes.data());
  p.step = std::ldexp(1.0, -shift);
}

// The bins either set uses, numbered in increasing order.
std::vector<std::uint32_t> used_bins(const DescriptorSet& a, const DescriptorSet& b, std::uint32_t& count) {
  std::vector<std::uint32_t> compact(a.dimension(), 0);
  for (const DescriptorSet* set : {&a, &b}) {
    for (const auto& h : set->sparse) {
      for (std::uint32_t bin : h.bins) compact[bin] = 1;
    }
  }
  count = 0;
  for (auto& c : compact) c = c ? count++ : 0;
  return compact;
}

void prepare_compact(const DescriptorSet& set, const std::vector<std::uint32_t>& compact, Prepared& p) {
  p.compact_begin.assign(1, 0);
  for (const auto& h : set.sparse) {
    for (std::uint32_t bin : h.bins) p.compact_bins.push_back(compact[bin]);
    p.compact_begin.push_back(p.compact_bins.size());
  }
}

void validate(const DescriptorSet& set, Distance metric, const char* which) {
  if (set.is_sparse()) {
    const std::uint32_t dim = set.sparse.front().dimension;
    for (const auto& h : set.sparse) {
      h.validate();
      if (h.dimension != dim) throw std::invalid_argument(std::string(which) + ": histograms differ in dimension");
    }
  } else if (metric == Distance::chi2) {
    for (float v : set.dense.values) {
      if (!(v >= 0.0F)) {
        throw std::invalid_argument(
            std::string(which) + ": the chi2 distance needs non-negative descriptors (histograms); use l1 or cosine");
      }
    }
  }
}

Prepared prepare(const DescriptorSet& set) {
  Prepared p;
  const std::size_t n = set.size();
  p.sum.resize(n);
  p.norm2.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (set.is_sparse()) {
      const auto& v = set.sparse[i].values;
      p.sum[i] = detail::sparse_sum(v.data(), v.size());
      p.norm2[i] = detail::sparse_sum_squares(v.data(), v.size());
    } else {
      p.norm2[i] = detail::lane_sum_squares(set.dense.row(i).data(), set.dense.cols);
    }
  }
  return p;
}

struct Tile {
  std::size_t row_begin, row_end, col_begin, col_end;
  bool diagonal;  // symmetric case: the tile reaches the diagonal, only cells with col < row are filled
};

double finish(Distance metric, double sum, double sum_a, double dimension, double norm2_a, double norm2_b) {
  switch (metric) {
    case Distance::chi2:
    case Distance::l1:
      return sum_a + sum;
    case Distance::sad:
      return dimension == 0 ? 0.0 : (sum_a + sum) / dimension;
    case Distance::cosine:
      return detail::cosine_from_dot(sum, norm2_a, norm2_b);
  }
  return 0.0;
}

// Sparse rows: groups of detail::kRows rows are scattered into `scratch` and compared with each column in
// one pass (kernels.hpp). Cells past the diagonal that a group's pass computes anyway are not stored.
void fill_sparse_tile(const Tile& t, const DescriptorSet& a, const Prepared& pa, const DescriptorSet& b,
                      const Prepared& pb, Distance metric, DenseMatrix<float>& out, std::vector<float>& scratch) {
  constexpr std::size_t G = detail::kRows;
  const auto kind = metric == Distance::chi2     ? detail::SparseSum::chi2
                    : metric == Distance::cosine ? detail::SparseSum::dot
                                                 : detail::SparseSum::l1;
  const double dim = static_cast<double>(a.dimension());
  for (std::size_t i0 = t.row_begin; i0 < t.row_end; i0 += G) {
    const std::size_t g = std::min(G, t.row_end - i0);
    const std::size_t col_end = t.diagonal ? std::min(t.col_end, i0 + g - 1) : t.col_end;
    if (col_end <= t.col_begin) continue;
    for (std::size_t r = 0; r < g; ++r) {
      const SparseHistogram& h = a.sparse[i0 + r];
      const std::uint32_t* bins = pa.compact_bins.data() + pa.compact_begin[i0 + r];
      for (std::size_t k = 0; k < h.bins.size(); ++k) scratch[static_cast<std::size_t>(bins[k]) * G + r] = h.values[k];
    }
    double sums[G];
    for (std::size_t j = t.col_begin; j < col_end; ++j) {
      const SparseHistogram& col = b.sparse[j];
      detail::sparse_sums(kind, scratch.data(), pb.compact_bins.data() + pb.compact_begin[j], col.values.data(),
                          col.bins.size(), sums);
      for (std::size_t r = 0; r < g; ++r) {
        const std::size_t i = i0 + r;
        if (t.diagonal && j >= i) continue;
        out(i, j) = static_cast<float>(finish(metric, sums[r], pa.sum[i], dim, pa.norm2[i], pb.norm2[j]));
      }
    }
    for (std::size_t r = 0; r < g; ++r) {
      const std::size_t i = i0 + r;
      for (std::size_t k = pa.compact_begin[i]; k < pa.compact_begin[i + 1]; ++k)
        scratch[static_cast<std::size_t>(pa.compact_bins[k]) * G + r] = 0.0F;
    }
  }
}

// L1 / SAD of rows on a byte grid, four columns per pass over the row: the same doubles as dense_l1.
void fill_byte_tile(const Tile& t, const Prepared& pa, const Prepared& pb, std::size_t n, Distance metric,
                    DenseMatrix<float>& out) {
  auto value = [&](std::uint64_t sum) {
    const double l1 = static_cast<double>(sum) * pa.step;  // exact, as dense_l1's sum is
    return static_cast<float>(metric == Distance::sad ? l1 / static_cast<double>(n) : l1);
  };
  for (std::size_t i = t.row_begin; i < t.row_end; ++i) {
    const std::size_t col_end = t.diagonal ? std::min(t.col_end, i) : t.col_end;
    const std::uint8_t* x = pa.bytes.data() + i * n;
    std::size_t j = t.col_begin;
    for (; j + 4 <= col_end; j += 4) {
      const std::uint8_t* const y[4] = {pb.bytes.data() + j * n, pb.bytes.data() + (j + 1) * n,
                                        pb.bytes.data() + (j + 2) * n, pb.bytes.data() + (j + 3) * n};
      std::uint64_t sums[4];
      detail::byte_l1_4(x, y, n, sums);
      for (std::size_t c = 0; c < 4; ++c) out(i, j + c) = value(sums[c]);
    }
    for (; j < col_end; ++j) out(i, j) = value(detail::byte_l1(x, pb.bytes.data() + j * n, n));
  }
}

void fill_dense_tile(const Tile& t, const DescriptorSet& a, const Prepared& pa, const DescriptorSet& b,
                     const Prepared& pb, Distance metric, DenseMatrix<float>& out) {
  if (!pa.bytes.empty()) return fill_byte_tile(t, pa, pb, a.dense.cols, metric, out);
  for (std::size_t i = t.row_begin; i < t.row_end; ++i) {
    const std::size_t col_end = t.diagonal ? std::min(t.col_end, i) : t.col_end;
    const float* x = a.dense.row(i).data();
    const std::size_t n = a.dense.cols;
    for (std::size_t j = t.col_begin; j < col_end; ++j) {
      const float* y = b.dense.row(j).data();
      double d = 0;
      switch (metric) {
        case Distance::chi2:
          d = detail::dense_chi2(x, y, n);
          break;
        case Distance::l1:
          d = detail::dense_l1(x, y, n);
          break;
        case Distance::sad:
          d = n == 0 ? 0.0 : detail::dense_l1(x, y, n) / static_cast<double>(n);
          break;
        case Distance::cosine:
          d = detail::cosine_from_dot(detail::dense_dot(x, y, n), pa.norm2[i], pb.norm2[j]);
          break;
      }
      out(i, j) = static_cast<float>(d);
    }
  }
}

DenseMatrix<float> compute(const DescriptorSet& a, const DescriptorSet& b, bool symmetric, Distance metric,
                           const MatrixConfig& config) {
  if (config.tile == 0) throw std::invalid_argument("distance matrix: tile size must be positive");
  const std::size_t rows = a.size(), cols = b.size();
  if (rows > 0 && cols > 0) {
    if (a.is_sparse() != b.is_sparse())
      throw std::invalid_argument("distance matrix: cannot compare sparse and dense descriptors");
    if (a.dimension() != b.dimension()) {
      throw std::invalid_argument("distance matrix: descriptors differ in dimension (" + std::to_string(a.dimension()) +
                                  " and " + std::to_string(b.dimension()) + ")");
    }
  }
  validate(a, metric, "first sequence");
  if (!symmetric) validate(b, metric, "second sequence");
  check_fits(matrix_bytes(rows, cols), config.memory_budget,
             "a " + std::to_string(rows) + " x " + std::to_string(cols) + " distance matrix");
  DenseMatrix<float> out(rows, cols, 0.0F);
  if (rows == 0 || cols == 0) return out;
  std::size_t scratch_size = 0;

  Prepared pa = prepare(a);
  Prepared pb = symmetric ? Prepared{} : prepare(b);
  if (a.is_sparse()) {
    std::uint32_t used = 0;
    const auto compact = used_bins(a, b, used);
    prepare_compact(a, compact, pa);
    if (!symmetric) prepare_compact(b, compact, pb);
    scratch_size = static_cast<std::size_t>(used) * detail::kRows;
  } else if (metric == Distance::l1 || metric == Distance::sad) {
    const int shift = common_byte_grid(a, b);
    if (shift >= 0) {
      prepare_bytes(a, shift, pa);
      if (!symmetric) prepare_bytes(b, shift, pb);
    }
  }
  const Prepared& pb_ref = symmetric ? pa : pb;

  const unsigned threads = config.threads > 0 ? config.threads : std::max(1U, std::thread::hardware_concurrency());
  // Tiles are `tile` columns wide (their descriptors stay in cache while the tile's rows pass over them)
  // and at most `tile` rows high, fewer for small matrices so that every thread gets several tiles.
  const std::size_t width = config.tile;
  const std::size_t height = std::clamp<std::size_t>((rows + 8 * threads - 1) / (8 * threads), 1, config.tile);
  std::vector<Tile> tiles;
  for (std::size_t r = 0; r < rows; r += height) {
    const std::size_t r_end = std::min(rows, r + height);
    for (std::size_t c = 0; c < (symmetric ? r_end : cols); c += width) {
      const std::size_t c_end = std::min(symmetric ? r_end : cols, c + width);
      tiles.push_back({r, r_end, c, c_end, symmetric && c_end > r});
    }
  }
  const std::size_t total_cells = symmetric ? rows * (rows - 1) / 2 : rows * cols;
  std::size_t done = 0;  // guarded by progress_mutex
  std::mutex progress_mutex;

  // Plain threads taking tiles from a shared counter: no thread ever waits for another until the end, which
  // matters on machines where the cores are shared (spinning barriers then cost whole time slices).
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(threads);
  auto worker = [&](unsigned id) {
    try {
      std::vector<float> scratch(scratch_size, 0.0F);
      for (std::size_t k = next.fetch_add(1); k < tiles.size(); k = next.fetch_add(1)) {
        const Tile& t = tiles[k];
        if (a.is_sparse()) {
          fill_sparse_tile(t, a, pa, b, pb_ref, metric, out, scratch);
        } else {
          fill_dense_tile(t, a, pa, b, pb_ref, metric, out);
        }
        if (config.progress) {
          std::size_t cells = 0;
          for (std::size_t i = t.row_begin; i < t.row_end; ++i) {
            const std::size_t end = t.diagonal ? std::min(t.col_end, i) : t.col_end;
            cells += end > t.col_begin ? end - t.col_begin : 0;
          }
          const std::lock_guard lock(progress_mutex);
          done += cells;
          config.progress(done, total_cells);
        }
      }
    } catch (...) {
      errors[id] = std::current_exception();
      next = tiles.size();  // the others stop after their current tile
    }
  };
  const unsigned workers = static_cast<unsigned>(std::min<std::size_t>(threads, tiles.size()));
  std::vector<std::thread> pool;
  pool.reserve(workers);
  for (unsigned id = 1; id < workers; ++id) pool.emplace_back(worker, id);
  worker(0);
  for (auto& thread : pool) thread.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  if (symmetric) {
    // Mirror the lower triangle in blocks so that both sides are walked cache-friendly.
    constexpr std::size_t block = 64;
    for (std::size_t bi = 0; bi < rows; bi += block) {
      for (std::size_t bj = bi; bj < rows; bj += block) {
        for (std::size_t i = bi; i < std::min(rows, bi + block); ++i) {
          for (std::size_t j = std::max(bj, i + 1); j < std::min(rows, bj + block); ++j) out(i, j) = out(j, i);
        }
      }
    }
  }
  return out;
}

}  // namespace

DenseMatrix<float> distance_matrix(const DescriptorSet& items, Distance metric, const MatrixConfig& config) {
  return compute(items, items, true, metric, config);
}

DenseMatrix<float> distance_matrix(const DescriptorSet& a, const DescriptorSet& b, Distance metric,
                                   const MatrixConfig& config) {
  return compute(a, b, false, metric, config);
}

}  // namespace seqtopo::similarity
