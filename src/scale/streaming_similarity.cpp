#include "seqtopo/scale/streaming_similarity.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace seqtopo::scale {
namespace {

using TilePtr = std::shared_ptr<const std::vector<float>>;

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

#if defined(__x86_64__)
// The instruction-set check of the alignment engine, asked once.
bool has_avx2() {
  static const bool avx2 = align::best_isa() == align::Isa::avx2;
  return avx2;
}
#endif

// out[r * out_stride + b] = sum over t = 0 .. dim-1, in order, of x[r * dim + t] * xt[t * stride + b]
// (no fused multiply-add): the dot products of `rows` rows with `count` columns.
void dot_block_portable(float* out, std::size_t out_stride, const float* x, std::size_t rows, const float* xt,
                        std::size_t stride, std::size_t dim, std::size_t count) {
  for (std::size_t r = 0; r < rows; ++r) {
    float* o = out + r * out_stride;
    std::fill(o, o + count, 0.0F);
    for (std::size_t t = 0; t < dim; ++t) {
      const float xa = x[r * dim + t];
      const float* col = xt + t * stride;
      for (std::size_t b = 0; b < count; ++b) o[b] += xa * col[b];
    }
  }
}

#if defined(__x86_64__)
// Four rows by sixteen columns at a time, the 8 sums in registers across the dimensions.
[[gnu::target("avx2")]] void dot_block_avx2(float* out, std::size_t out_stride, const float* x, std::size_t rows,
                                            const float* xt, std::size_t stride, std::size_t dim, std::size_t count) {
  std::size_t r = 0;
  for (; r + 4 <= rows; r += 4) {
    std::size_t b = 0;
    for (; b + 16 <= count; b += 16) {
      __m256 acc[4][2];
      for (auto& row : acc) row[0] = row[1] = _mm256_setzero_ps();
      for (std::size_t t = 0; t < dim; ++t) {
        const __m256 c0 = _mm256_loadu_ps(xt + t * stride + b), c1 = _mm256_loadu_ps(xt + t * stride + b + 8);
        for (std::size_t u = 0; u < 4; ++u) {
          const __m256 xa = _mm256_broadcast_ss(x + (r + u) * dim + t);
          acc[u][0] = _mm256_add_ps(acc[u][0], _mm256_mul_ps(xa, c0));
          acc[u][1] = _mm256_add_ps(acc[u][1], _mm256_mul_ps(xa, c1));
        }
      }
      for (std::size_t u = 0; u < 4; ++u) {
        _mm256_storeu_ps(out + (r + u) * out_stride + b, acc[u][0]);
        _mm256_storeu_ps(out + (r + u) * out_stride + b + 8, acc[u][1]);
      }
    }
    if (b < count) {
      dot_block_portable(out + r * out_stride + b, out_stride, x + r * dim, 4, xt + b, stride, dim, count - b);
    }
  }
  if (r < rows) dot_block_portable(out + r * out_stride, out_stride, x + r * dim, rows - r, xt, stride, dim, count);
}
#endif

void dot_block(float* out, std::size_t out_stride, const float* x, std::size_t rows, const float* xt,
               std::size_t stride, std::size_t dim, std::size_t count) {
#if defined(__x86_64__)
  if (has_avx2()) return dot_block_avx2(out, out_stride, x, rows, xt, stride, dim, count);
#endif
  dot_block_portable(out, out_stride, x, rows, xt, stride, dim, count);
}

[[gnu::target_clones("avx2", "default")]] void finish(float* out, const float* v, const double* rs, const double* rs2,
                                                      const double* row_count, const double* cs, const double* cs2,
                                                      double col_count, float offset, std::size_t count) {
  for (std::size_t b = 0; b < count; ++b) {
    const float e_ij = similarity::contrast_score(v[b], rs[b], rs2[b], row_count[b]);
    const float e_ji = similarity::contrast_score(v[b], cs[b], cs2[b], col_count);
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
    if (!std::isfinite(norm2)) throw std::invalid_argument("descriptor " + std::to_string(i) + " is not finite");
    // A zero descriptor (a uniform image's patch: a tunnel, a covered lens) has no direction: it stays zero, cosine 0
    // with every frame, itself included; such frames are masked as of little information (significance/).
    const double inv = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
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
    const std::size_t first = similarity::first_read(centre, w), end = std::min(n_, centre + w + 1);
    std::vector<float> row(end - first);
    for (std::size_t k = first; k < end; ++k) row[k - first] = cosine(fixed, k);
    double sum = 0, sum2 = 0, count = 0;
    similarity::window_sums_of(&sum, &sum2, &count, row.data(), first, n_, w, centre, centre + 1);
    return similarity::contrast_score(v, sum, sum2, count);
  };
  // E(i, j): row i around column j; E(j, i): row j around column i.
  return combine(window_stats(i, j), window_stats(j, i), config_.contrast_offset);
}

std::vector<float> StreamingSimilarity::compute_tile(std::size_t tile_row, std::size_t tile_col) const {
  const std::size_t T = config_.tile, w = config_.contrast_window;
  const std::size_t r0 = tile_row * T, r1 = std::min(n_, r0 + T);
  const std::size_t c0 = tile_col * T, c1 = std::min(n_, c0 + T);
  // Widened by the window (and for running sums back to the restart before the tile: similarity::first_read).
  const std::size_t er0 = similarity::first_read(r0, w), er1 = std::min(n_, r1 + w);
  const std::size_t ec0 = similarity::first_read(c0, w), ec1 = std::min(n_, c1 + w);
  const std::size_t ew = ec1 - ec0, tw = c1 - c0;

  // Raw cosine on the widened tile; each cell summed in dimension order (vectorised across columns).
  std::vector<float> raw((er1 - er0) * ew);
  kernels::dot_block(raw.data(), ew, normalized_.data() + er0 * dim_, er1 - er0, transposed_.data() + ec0, n_, dim_,
                     ew);

  std::vector<float> tile((r1 - r0) * tw);
  if (w == 0) {
    for (std::size_t i = r0; i < r1; ++i) {
      const float* row = raw.data() + (i - er0) * ew + (c0 - ec0);
      for (std::size_t j = 0; j < tw; ++j) tile[(i - r0) * tw + j] = combine(row[j], row[j], config_.contrast_offset);
    }
    return tile;
  }
  std::vector<double> rs(tw), rs2(tw), row_count(tw), cs(tw), cs2(tw);
  // Column j around row i (= row j around column i, the cosine being symmetric bit for bit): rows i - w .. i + w,
  // clipped, for all the tile's columns at once, by similarity::window_sums_of's arithmetic (a running sum from
  // the restart before r0 for a wide window).
  const bool running = w >= similarity::kRunningWindow;
  const auto raw_row = [&](std::size_t k) { return raw.data() + (k - er0) * ew + (c0 - ec0); };
  for (std::size_t i = running ? r0 - r0 % similarity::kRunningBlock : r0; i < r1; ++i) {
    const std::size_t klo = i > w ? i - w : 0, khi = std::min(n_, i + w + 1);
    if (!running || i % similarity::kRunningBlock == 0) {
      similarity::window_sums(cs.data(), cs2.data(), raw_row(klo), ew, khi - klo, tw);
    } else {
      similarity::running_window_step(cs.data(), cs2.data(), i + w < n_ ? raw_row(i + w) : nullptr,
                                      i > w ? raw_row(i - w - 1) : nullptr, tw);
    }
    if (i < r0) continue;
    // Row i around column j: columns j - w .. j + w, clipped to the matrix.
    const float* row = raw.data() + (i - er0) * ew;
    similarity::window_sums_of(rs.data(), rs2.data(), row_count.data(), row, ec0, n_, w, c0, c1);
    kernels::finish(tile.data() + (i - r0) * tw, row + (c0 - ec0), rs.data(), rs2.data(), row_count.data(), cs.data(),
                    cs2.data(), static_cast<double>(khi - klo), config_.contrast_offset, tw);
  }
  return tile;
}

TilePtr StreamingSimilarity::tile(std::size_t tile_row, std::size_t tile_col, bool wait) const {
  const std::size_t tiles_per_band = (n_ + config_.tile - 1) / config_.tile;
  const std::uint64_t key = static_cast<std::uint64_t>(tile_row) * tiles_per_band + tile_col;
  std::promise<TilePtr> promise;
  std::shared_future<TilePtr> future;
  {
    std::lock_guard lock(cache_->mutex);
    auto it = cache_->entries.find(key);
    if (it != cache_->entries.end()) {
      it->second.last_use = ++cache_->clock;
      if (!wait) return nullptr;
      future = it->second.tile;
    } else {
      if (cache_->entries.size() >= cache_->capacity) {
        auto oldest =
            std::min_element(cache_->entries.begin(), cache_->entries.end(),
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
  if (i >= n_ || j_end > n_ || j_begin > j_end)
    throw std::out_of_range("streaming similarity: row segment out of range");
  const std::size_t T = config_.tile;
  const std::size_t tr = i / T;
  // First compute the segment's missing tiles, skipping those another reader is computing: concurrent
  // readers of one band (the forward and the reverse pass) then share the work instead of waiting.
  if (j_end > j_begin) {
    for (std::size_t tc = j_begin / T; tc <= (j_end - 1) / T; ++tc) tile(tr, tc, false);
  }
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
  return align::ScoreSource(
      n_, n_,
      [this](std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) { read_row(i, j_begin, j_end, out); },
      [this](std::size_t i, std::size_t j) { return score(i, j); });
}

StreamingStats StreamingSimilarity::stats() const {
  std::lock_guard lock(cache_->mutex);
  return cache_->stats;
}

}  // namespace seqtopo::scale
