#pragma once
// The mapping score S(i, j) computed on the fly from per-frame descriptors, never holding N x N.
//
// Distance: cosine similarity of the descriptors, raw(i, j) = x_i . x_j / (|x_i| |x_j|) (rows are
// normalised once, in float). The mapping score is then the map's contrast enhancement
// (similarity/contrast_enhancement.hpp, mapping::MapConfig):
//   score(i, j) = 0.5 (E(i, j) + E(j, i)) - offset,  E(i, j) = (raw(i, j) - mean) / sd
// with mean and sd of row i of raw over columns j - window .. j + window (clipped to the matrix). For the
// symmetric raw matrix, E(j, i) uses row j around column i, i.e. column j over rows i - window .. i + window,
// so a tile of scores needs only the raw tile widened by `window` on each side.
//
// The arithmetic (float dot products summed in dimension order, window sums in double in index order)
// is the one of the dense path, so score(i, j) equals
//   enhance_contrast_symmetric(dense cosine matrix, window, offset)(i, j)
// bit for bit, for any tile size and thread count.
//
// Tiles of tile x tile scores are computed when first read and kept in a small cache (least recently
// used first out), so a row-by-row reader costs one tile band. Memory: the normalised descriptors
// (N x dim floats) plus the cache (cache_tiles x tile^2 floats).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "seqtopo/align/score_source.hpp"

namespace seqtopo::scale {

struct StreamingConfig {
  std::size_t contrast_window = 10;  // [frames]; 0 = raw cosine, symmetrised, minus the offset
  float contrast_offset = 0.5F;      // [standard deviations]
  std::size_t tile = 256;            // tile side [cells]
  // Tiles kept; 0 = enough for two full bands of tiles (a forward and a reverse reader).
  std::size_t cache_tiles = 0;
};

struct StreamingStats {
  std::uint64_t tiles_computed = 0;  // including recomputations after eviction
  std::uint64_t cells_computed = 0;
  std::size_t cache_bytes = 0;  // the cache's capacity [bytes]
};

class StreamingSimilarity {
 public:
  // descriptors: n x dim, row-major (copied and normalised; a zero one stays zero: cosine 0 with every frame).
  // Throws std::invalid_argument on a size mismatch, dim = 0, a non-finite descriptor, or tile = 0.
  StreamingSimilarity(std::span<const float> descriptors, std::size_t n, std::size_t dim, StreamingConfig config = {});
  ~StreamingSimilarity();
  StreamingSimilarity(const StreamingSimilarity&) = delete;
  StreamingSimilarity& operator=(const StreamingSimilarity&) = delete;

  std::size_t size() const { return n_; }
  std::size_t dim() const { return dim_; }
  const StreamingConfig& config() const { return config_; }
  // The normalised descriptors, n x dim row-major.
  std::span<const float> normalized() const { return normalized_; }

  // score(i, j) for j in [j_begin, j_end) into out. Safe to call from several threads at once.
  void read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) const;
  // One cell, computed directly (2 (2 window + 1) dot products, no cache): the same value as read_row.
  float score(std::size_t i, std::size_t j) const;
  // raw(i, j), the cosine similarity.
  float cosine(std::size_t i, std::size_t j) const;
  // A ScoreSource reading this object (which must outlive it).
  align::ScoreSource source() const;

  StreamingStats stats() const;

 private:
  struct Cache;
  // The tile, from the cache or computed by this thread. Without `wait`, a tile already in the cache or
  // being computed by another thread is not waited for (nullptr is returned).
  std::shared_ptr<const std::vector<float>> tile(std::size_t tile_row, std::size_t tile_col, bool wait = true) const;
  std::vector<float> compute_tile(std::size_t tile_row, std::size_t tile_col) const;

  std::size_t n_, dim_;
  StreamingConfig config_;
  std::vector<float> normalized_;  // n x dim
  std::vector<float> transposed_;  // dim x n
  std::unique_ptr<Cache> cache_;
};

}  // namespace seqtopo::scale
