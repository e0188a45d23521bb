#pragma once
// Smith-Waterman on a sparse score matrix: a constant `background` score everywhere except at listed
// candidate cells (for instance the approximate nearest neighbours of each frame, sparse_candidates.hpp).
//
// Why it is cheap: with background < 0 and gaps > 0, the cumulative score H falls by at least
// min(-background, gap) per step away from a candidate, so H is positive only in a bounded neighbourhood
// downstream of the positive candidates. The fill visits only those cells (row by row, seeded by the
// candidates and by the previous row's positive cells), groups the positive cells into connected
// components of the recurrence (a cell joins the components of its positive predecessors), and runs
// the exact engine (smith_waterman.hpp) on each component's bounding box that can reach the threshold.
// Outside a component H is 0 at all times, and taking an alignment only lowers H downstream of it, so
// the components never interact: the alignments are exactly those of local_alignments() on the dense
// matrix with the same candidate scores and the background elsewhere (with cap, threshold, direction,
// self band; tested against it on random cases).
//
// Order: one pass returns its alignments by decreasing score, then a_begin, then b_begin (the dense
// engine breaks score ties by the row-major position of the alignment's end instead); the merge of both
// passes is the dense one (local_alignments_both), so with max_alignments unlimited the result of
// sparse_local_alignments_both equals local_alignments_both exactly.
//
// The pass as separate steps (components, one box each, the merge) for spreading the work elsewhere:
// sparse_components.hpp.
//
// Memory: the candidates; the fill's last two rows of positive cells (12 bytes each), 8 bytes per
// component label (one per cell without a positive predecessor, at most one per positive candidate), the
// working state of the components that still have a cell in the current row, and each component kept
// (reaching the threshold) as runs of consecutive cells: 8 bytes per row and 8 per run; then the largest
// component box (5 bytes per cell). A component that touches the self band's edge is aligned in a square
// box on the diagonal (the engine's band needs the diagonal), so a long revisit hugging the band edge
// costs its length squared.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::scale {

struct SparseEntry {
  std::uint32_t i = 0, j = 0;
  float score = 0;
};

// A rows x cols score matrix: `background` except at the entries (compressed rows, columns sorted).
class SparseScores {
 public:
  SparseScores() = default;
  // Throws std::invalid_argument on an entry outside the matrix, a repeated cell or a non-finite score.
  SparseScores(std::size_t rows, std::size_t cols, float background, std::vector<SparseEntry> entries);

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }
  float background() const { return background_; }
  std::size_t entries() const { return columns_.size(); }
  float at(std::size_t i, std::size_t j) const;
  // Row i's candidate columns and scores (columns increasing).
  std::span<const std::uint32_t> row_columns(std::size_t i) const;
  std::span<const float> row_values(std::size_t i) const;
  // The equivalent dense matrix as a ScoreSource (reads this object, which must outlive it).
  align::ScoreSource source() const;
  void read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) const;

 private:
  std::size_t rows_ = 0, cols_ = 0;
  float background_ = -1.0F;
  std::vector<std::size_t> row_begin_{0};
  std::vector<std::uint32_t> columns_;
  std::vector<float> values_;
};

struct SparseAlignStats {
  std::size_t active_cells = 0;        // cells with H > 0 in the first fill (both passes)
  std::size_t components = 0;          // connected components of them
  std::size_t aligned_components = 0;  // those whose best cell reaches the threshold
  std::size_t box_cells = 0;           // cells of all boxes given to the exact engine
  std::size_t largest_box_cells = 0;
};

// One pass (config.direction). Throws std::invalid_argument like local_alignments(), and unless
// background < 0 and both gaps > 0 (otherwise H need not decay and nothing is sparse).
std::vector<align::LocalAlignment> sparse_local_alignments(const SparseScores& scores, const align::AlignConfig& config,
                                                           SparseAlignStats* stats = nullptr);
// Forward and reverse (concurrently when threads > 1), merged as local_alignments_both() merges them.
std::vector<align::LocalAlignment> sparse_local_alignments_both(const SparseScores& scores, align::AlignConfig config,
                                                                unsigned threads = 2,
                                                                SparseAlignStats* stats = nullptr);

}  // namespace seqtopo::scale
