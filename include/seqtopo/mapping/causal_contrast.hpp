#pragma once
// Causal contrast enhancement: the offline map's local contrast enhancement (similarity/contrast_enhancement.hpp,
// the symmetric form 0.5 (E + E^T)) for a similarity that arrives one row at a time, each score computed once and
// never changed. Row t holds S(t, j) for the earlier frames j < t; its enhanced score at column j is
//   0.5 (z_row(t, j) + z_col(t, j)),
// z_row the z-score of S(t, j) among S(t, j - w .. j + w) (clipped to the past, j' < t), z_col its z-score among
// S(t - w .. t, j) (the column's last w + 1 values, rows that have column j: the window one-sided, because the later
// rows are not known yet). Several similarities are enhanced each on its own and their enhanced scores averaged, as
// the offline fusion does (mapping::enhanced_scores), so their scales need not agree. w = 0: the rows averaged as
// they are. Work per row O(t) whatever the window (prefix sums for the rows, w + 1 rows kept for the columns);
// memory O(t w) per similarity. Used by the online mapper (mapping/online_mapper.hpp).
#include <cstddef>
#include <span>
#include <vector>

namespace seqtopo::mapping {

class CausalContrast {
 public:
  explicit CausalContrast(std::size_t window = 10) : window_(window) {}

  // Row t = rows() of every similarity (t values each, the same number of similarities every row): the fused
  // enhanced scores of its first n <= t columns into `out` (n values).
  void add(const std::vector<std::span<const float>>& rows, std::size_t n, std::vector<float>& out);
  std::size_t rows() const { return rows_; }
  std::size_t window() const { return window_; }

 private:
  std::size_t window_;
  std::size_t rows_ = 0;
  std::vector<std::vector<std::vector<float>>> recent_;  // per similarity: its last w + 1 rows, by row modulo w + 1
  std::vector<double> prefix_, prefix2_;                 // the row's running sums (reused)
  std::vector<float> enhanced_;                          // the row z-scores (reused)
};

}  // namespace seqtopo::mapping
