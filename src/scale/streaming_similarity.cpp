#include "seqtopo/scale/streaming_similarity.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace seqtopo::scale {
namespace {

using TilePtr = std::shared_ptr<const std::vector<float>>;

// The dense path's arithmetic (enhance_contrast): window sums in double, in index order.
float enhanced(float v, double sum, double sum2, double count) {
  const double mean = sum / count;
  const double sd = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
  return static_cast<float>((v - mean) / std::max(sd, 1e-9));
}

float combine(float e_ij, float e_ji, float offset) { return 0.5F * (e_ij + e_ji) - offset; }

// Float dot product summed in dimension order (the order the tile kernel uses per cell).
float dot(const float* x, const float* y, std::size_t dim) {
  float s = 0.0F;
  for (std::size_t t = 0; t < dim; ++t) s += x[t] * y[t];
  return s;
}

// The tile's inner loops, compiled for AVX2 and for the baseline and picked at load time. Both keep
// every cell's operations and their order (no fused multiply-add: -ffp-contract=off), so the result
// does not depend on the machine.
namespace kernels {

// out[b] += x[t] * xt[t * stride + b] for t = 0 .. dim-1 in order: dot products of x with `count` columns.
[[gnu::target_clones("avx2", "default")]] void dot_row(float* out, const float* x, const float* xt,
                                                        std::size_t stride, std::size_t dim, std::size_t count) {
  for (std::size_t t = 0; t < dim; ++t) {
    const float xa = x[t];
    const float* col = xt + t * stride;
    for (std::size_t b = 0; b < count; ++b) out[b] += xa * col[b];
  }
}

[[gnu::target_clones("avx2", "default")]] void accumulate(double* sum, double* sum2, const float* v, std::size_t count) {
  for (std::size_t b = 0; b < count; ++b) {
    sum[b] += v[b];
    sum2[b] += static_cast<double>(v[b]) * v[b];
  }
}

[[gnu::target_clones("avx2", "default")]] void finish(float* out, const float* v, const double* rs, const double* rs2,
                                                       const double* row_count, const double* cs, const double* cs2,
                                                       double col_count, float offset, std::size_t count) {
  for (std::size_t b = 0; b < count; ++b) {
    const float e_ij = enhanced(v[b], rs[b], rs2[b], row_count[b]);
    const float e_ji = enhanced(v[b], cs[b], cs2[b], col_count);
    out[b] = combine(e_ij, e_ji, offset);
  }
}

}  // namespace kernels
}  // namespace

struct StreamingSimilarity::Cache {
  struct Entry {
    std::shared_future<TilePtr> tile;
    std::uint64_t last_use = 0;
  };
  std::mutex mutex;
  std::unordered_map<std::uint64_t, Entry> entries;
  std::uint64_t clock = 0;
  std::size_t capacity = 0;
  StreamingStats stats;
};

StreamingSimilarity::StreamingSimilarity(std::span<const float> descriptors, std::size_t n, std::size_t dim,
                                         StreamingConfig config)
    : n_(n), dim_(dim), config_(config), cache_(std::make_unique<Cache>()) {
  if (dim == 0) throw std::invalid_argument("descriptors need at least one dimension");
  if (descriptors.size() != n * dim) {
    throw std::invalid_argument("descriptors have " + std::to_string(descriptors.size()) + " values, expected " +
                                std::to_string(n) + " x " + std::to_string(dim));
  }
  if (config_.tile == 0) throw std::invalid_argument("tile side must be >= 1");
  normalized_.resize(n * dim);
  transposed_.resize(n * dim);
  for (std::size_t i = 0; i < n; ++i) {
    const float* x = descriptors.data() + i * dim;
    double norm2 = 0;
    for (std::size_t t = 0; t < dim; ++t) norm2 += static_cast<double>(x[t]) * x[t];
    if (!(norm2 > 0) || !std::isfinite(norm2)) {
      throw std::invalid_argument("descriptor " + std::to_string(i) + " is zero or not finite (cosine needs a direction)");
    }
    const double inv = 1.0 / std::sqrt(norm2);
    for (std::size_t t = 0; t < dim; ++t) {
      const auto v = static_cast<float>(x[t] * inv);
      normalized_[i * dim + t] = v;
      transposed_[t * n + i] = v;
    }
  }
  const std::size_t tiles_per_band = (n + config_.tile - 1) / config_.tile;
  cache_->capacity = config_.cache_tiles != 0 ? config_.cache_tiles : std::max<std::size_t>(4, 3 * tiles_per_band);
  cache_->stats.cache_bytes = cache_->capacity * config_.tile * config_.tile * sizeof(float);
}

StreamingSimilarity::~StreamingSimilarity() = default;

float StreamingSimilarity::cosine(std::size_t i, std::size_t j) const {
  return dot(normalized_.data() + i * dim_, normalized_.data() + j * dim_, dim_);
}

float StreamingSimilarity::score(std::size_t i, std::size_t j) const {
  if (i >= n_ || j >= n_) throw std::out_of_range("streaming similarity: cell out of range");
  const std::size_t w = config_.contrast_window;
  const float v = cosine(i, j);
  if (w == 0) return combine(v, v, config_.contrast_offset);
  auto window_stats = [&](std::size_t fixed, std::size_t centre) {
    const std::size_t lo = centre > w ? centre - w : 0;
    const std::size_t hi = std::min(n_, centre + w + 1);
    double sum = 0, sum2 = 0;
    for (std::size_t k = lo; k < hi; ++k) {
      const float r = cosine(fixed, k);
      sum += r;
      sum2 += static_cast<double>(r) * r;
    }
    return enhanced(v, sum, sum2, static_cast<double>(hi - lo));
  };
  // E(i, j): row i around column j; E(j, i): row j around column i.
  return combine(window_stats(i, j), window_stats(j, i), config_.contrast_offset);
}

std::vector<float> StreamingSimilarity::compute_tile(std::size_t tile_row, std::size_t tile_col) const {
  const std::size_t T = config_.tile, w = config_.contrast_window;
  const std::size_t r0 = tile_row * T, r1 = std::min(n_, r0 + T);
  const std::size_t c0 = tile_col * T, c1 = std::min(n_, c0 + T);
  const std::size_t er0 = r0 > w ? r0 - w : 0, er1 = std::min(n_, r1 + w);
  const std::size_t ec0 = c0 > w ? c0 - w : 0, ec1 = std::min(n_, c1 + w);
  const std::size_t ew = ec1 - ec0, tw = c1 - c0;

  // Raw cosine on the widened tile; each cell summed in dimension order (vectorised across columns).
  std::vector<float> raw((er1 - er0) * ew, 0.0F);
  for (std::size_t a = er0; a < er1; ++a) {
    kernels::dot_row(raw.data() + (a - er0) * ew, normalized_.data() + a * dim_, transposed_.data() + ec0, n_, dim_, ew);
  }

  std::vector<float> tile((r1 - r0) * tw);
  std::vector<double> rs(tw), rs2(tw), cs(tw), cs2(tw), row_count(tw);
  for (std::size_t j = c0; j < c1; ++j) {
    const std::size_t lo = j > w ? j - w : 0, hi = std::min(n_, j + w + 1);
    row_count[j - c0] = static_cast<double>(hi - lo);
  }
  const auto wi = static_cast<std::ptrdiff_t>(w);
  const auto n = static_cast<std::ptrdiff_t>(n_);
  for (std::size_t i = r0; i < r1; ++i) {
    const float* row = raw.data() + (i - er0) * ew;
    float* out = tile.data() + (i - r0) * tw;
    if (w == 0) {
      for (std::size_t j = 0; j < tw; ++j) {
        const float v = row[c0 - ec0 + j];
        out[j] = combine(v, v, config_.contrast_offset);
      }
      continue;
    }
    std::fill(rs.begin(), rs.end(), 0.0);
    std::fill(rs2.begin(), rs2.end(), 0.0);
    std::fill(cs.begin(), cs.end(), 0.0);
    std::fill(cs2.begin(), cs2.end(), 0.0);
    // Row i around column j: columns j + o for o = -w .. w (index order), where inside the matrix.
    for (std::ptrdiff_t o = -wi; o <= wi; ++o) {
      const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(c0), -o);
      const std::ptrdiff_t hi = std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(c1), n - o);
      if (hi <= lo) continue;
      const auto jlo = static_cast<std::size_t>(lo);
      kernels::accumulate(rs.data() + (jlo - c0), rs2.data() + (jlo - c0),
                          row + static_cast<std::size_t>(lo + o) - ec0, static_cast<std::size_t>(hi - lo));
    }
    // Column j around row i (= row j around column i): rows i + o, where inside the matrix.
    const std::size_t klo = i > w ? i - w : 0, khi = std::min(n_, i + w + 1);
    for (std::size_t k = klo; k < khi; ++k) {
      kernels::accumulate(cs.data(), cs2.data(), raw.data() + (k - er0) * ew + (c0 - ec0), tw);
    }
    kernels::finish(out, row + (c0 - ec0), rs.data(), rs2.data(), row_count.data(), cs.data(), cs2.data(),
                    static_cast<double>(khi - klo), config_.contrast_offset, tw);
  }
  return tile;
}

TilePtr StreamingSimilarity::tile(std::size_t tile_row, std::size_t tile_col) const {
  const std::size_t tiles_per_band = (n_ + config_.tile - 1) / config_.tile;
  const std::uint64_t key = static_cast<std::uint64_t>(tile_row) * tiles_per_band + tile_col;
  std::promise<TilePtr> promise;
  std::shared_future<TilePtr> future;
  {
    std::lock_guard lock(cache_->mutex);
    auto it = cache_->entries.find(key);
    if (it != cache_->entries.end()) {
      it->second.last_use = ++cache_->clock;
      future = it->second.tile;
    } else {
      if (cache_->entries.size() >= cache_->capacity) {
        auto oldest = std::min_element(cache_->entries.begin(), cache_->entries.end(),
                                       [](const auto& a, const auto& b) { return a.second.last_use < b.second.last_use; });
        cache_->entries.erase(oldest);
      }
      Cache::Entry entry{promise.get_future().share(), ++cache_->clock};
      cache_->entries.emplace(key, entry);
      ++cache_->stats.tiles_computed;
      const std::size_t rows = std::min(config_.tile, n_ - tile_row * config_.tile);
      const std::size_t cols = std::min(config_.tile, n_ - tile_col * config_.tile);
      cache_->stats.cells_computed += rows * cols;
      // This thread computes it (future stays empty); others wait on the entry's future.
    }
  }
  if (future.valid()) return future.get();
  try {
    auto values = std::make_shared<const std::vector<float>>(compute_tile(tile_row, tile_col));
    promise.set_value(values);
    return values;
  } catch (...) {
    promise.set_exception(std::current_exception());
    throw;
  }
}

void StreamingSimilarity::read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) const {
  if (i >= n_ || j_end > n_ || j_begin > j_end) throw std::out_of_range("streaming similarity: row segment out of range");
  const std::size_t T = config_.tile;
  const std::size_t tr = i / T;
  std::size_t j = j_begin;
  while (j < j_end) {
    const std::size_t tc = j / T;
    const std::size_t c0 = tc * T, c1 = std::min(n_, c0 + T);
    const std::size_t stop = std::min(j_end, c1);
    const TilePtr values = tile(tr, tc);
    const float* src = values->data() + (i - tr * T) * (c1 - c0) + (j - c0);
    std::copy(src, src + (stop - j), out);
    out += stop - j;
    j = stop;
  }
}

align::ScoreSource StreamingSimilarity::source() const {
  return align::ScoreSource(n_, n_, [this](std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) {
    read_row(i, j_begin, j_end, out);
  });
}

StreamingStats StreamingSimilarity::stats() const {
  std::lock_guard lock(cache_->mutex);
  return cache_->stats;
}

}  // namespace seqtopo::scale
