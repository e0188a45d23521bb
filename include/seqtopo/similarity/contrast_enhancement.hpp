#pragma once
// Local contrast enhancement of a similarity matrix (as in SeqSLAM, Milford & Wyeth 2012): the one
// implementation behind `seqtopo map` (dense and streamed), `seqtopo localize` and the SeqSLAM baseline.
//
// Why: a raw similarity matrix has strong row and column structure - some frames (dark, blurred,
// featureless) are similar to everything, others to nothing - so one global threshold S > 0
// rewards aliasing in some rows and misses true revisits in others. Normalising every cell by the
// mean and standard deviation of its row within +-window columns turns it into "how many standard
// deviations better than its neighbours", which is comparable across the whole matrix.
//
// Arithmetic (fixed, so that every caller gets the same bits): the window's sum and sum of squares are
// accumulated in double from the float cells; then
//   z = (v - mean) / max(sd, 1e-9),  mean = sum / count,  sd = sqrt(max(0, sum2 / count - mean^2))
// in double, rounded to float once. Windows are clipped at the matrix's edges. A window narrower than
// kRunningWindow cells either side is summed term by term, in index order. A wider one is a running sum (O(1) a
// cell whatever the window, as an integral image): at each multiple of kRunningBlock the window is summed term by
// term, and each next cell adds the value entering its window, then subtracts the one leaving it. The restarts are
// at fixed columns, so a reader of part of a row (a streamed tile) gets the bits of the whole row.
#include <cstddef>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::similarity {

inline constexpr std::size_t kRunningWindow = 32;  // [cells either side] from this window on, running sums
inline constexpr std::size_t kRunningBlock = 64;   // [cells] a running sum restarts at each multiple of this

// The first index whose value the window sums of cells [begin, ...) read (window w either side): begin - w, or
// for a running sum the block start of `begin` minus w (clipped at 0).
std::size_t first_read(std::size_t begin, std::size_t w);

// One step of the running sums of `count` windows at once (cells of a row, or the same cell of `count` columns):
// the values entering the windows added (entering null: none), then the values leaving subtracted (leaving null:
// none), each as x and x * x in double. Inline: a row's running sums take one step a cell.
inline void running_window_step(double* sum, double* sum2, const float* entering, const float* leaving,
                                std::size_t count) {
  if (entering != nullptr) {
    for (std::size_t b = 0; b < count; ++b) {
      const double v = entering[b];
      sum[b] += v;
      sum2[b] += v * v;
    }
  }
  if (leaving != nullptr) {
    for (std::size_t b = 0; b < count; ++b) {
      const double v = leaving[b];
      sum[b] -= v;
      sum2[b] -= v * v;
    }
  }
}

// sum[c - begin], sum2[c - begin] and count[c - begin] for cells c in [begin, end) (end <= n) of a row of n
// values, value k at x[k - x0] for k in [first_read(begin, w), min(n, end + w)) (x0 <= first_read(begin, w)): the
// sums over the window [c - w, c + w] clipped to [0, n), by the arithmetic above.
void window_sums_of(double* sum, double* sum2, double* count, const float* x, std::size_t x0, std::size_t n,
                    std::size_t w, std::size_t begin, std::size_t end);

// The z-score of v in a window of `count` cells with these sums.
float contrast_score(float v, double sum, double sum2, double count);

// sum[b] and sum2[b] over first[t * stride + b] for t = 0 .. terms - 1, in that order, for b < count: the
// window sums of `count` consecutive cells at once (vectorised across b; the same bits as one cell at a time).
void window_sums(double* sum, double* sum2, const float* first, std::size_t stride, std::size_t terms,
                 std::size_t count);

// One row: out[c] = contrast_score of row[c] within columns [c - window, c + window] (clipped). window >= cols
// uses the whole row for every cell. `out` may not alias `row`.
void enhance_row(const float* row, std::size_t cols, std::size_t window, float* out);

// out[c] of enhance_row for c < end only (end <= cols), the same bits, the rest of out untouched: for readers
// of part of a row (the SeqSLAM-style baseline's self mode reads only frames at least min_separation back).
void enhance_row_prefix(const float* row, std::size_t cols, std::size_t window, std::size_t end, float* out);

// Every row enhanced (enhance_row). window = 0 returns the matrix unchanged.
SimilarityMatrix enhance_contrast(const SimilarityMatrix& similarity, std::size_t window);

// For a square (self-similarity) matrix: 0.5 (E + E^T) - offset, with E = enhance_contrast(S, window).
// Symmetric again, and positive only where a cell stands out by more than `offset` standard
// deviations: the alignment rewards those and penalises the rest.
SimilarityMatrix enhance_contrast_symmetric(const SimilarityMatrix& similarity, std::size_t window, float offset);

}  // namespace seqtopo::similarity
