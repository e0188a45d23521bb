#pragma once
// Where the alignment engine gets the score of pairing element i of A with element j of B.
//
// Images, fingerprints and DNA letters are three ways of producing such a score; the engine does not
// care which. A source is a dense row-major matrix (not owned: the caller keeps it alive) or any
// callable `score(i, j)`. The engine reads it a row segment at a time, so a callable costs one
// indirect call per row segment, not per cell.
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

namespace seqtopo::align {

using Score = float;

class ScoreSource {
 public:
  // Fills out[0 .. j_end - j_begin) with score(i, j) for j in [j_begin, j_end).
  using RowReader = std::function<void(std::size_t i, std::size_t j_begin, std::size_t j_end, Score* out)>;

  // One cell, for sources where a single cell is cheaper computed on its own than through a row segment (a
  // streamed similarity computes a whole tile for a segment).
  using CellReader = std::function<Score(std::size_t i, std::size_t j)>;

  ScoreSource(std::size_t rows, std::size_t cols, RowReader reader, CellReader cell = {});

  // A dense row-major rows x cols matrix. Throws std::invalid_argument if the size does not match.
  static ScoreSource dense(std::span<const float> values, std::size_t rows, std::size_t cols);
  static ScoreSource dense(std::span<const double> values, std::size_t rows, std::size_t cols);
  // Any callable; it must be safe to call from two threads at once (forward and reverse passes).
  static ScoreSource function(std::size_t rows, std::size_t cols, std::function<Score(std::size_t, std::size_t)> score);
  // The same rows and columns read through another reader, one that changes each cell of this source cheaply
  // (an offset, a mask): in memory when this source is.
  ScoreSource derived(RowReader reader, CellReader cell = {}) const;
  // The rows and columns `frames` (ascending, each < rows() and < cols()) of this source, in that order: row k is
  // this source's row frames[k] read at columns frames[...]. In memory when this source is (a gather of its rows).
  ScoreSource subset(std::vector<std::size_t> frames) const;

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }
  void read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, Score* out) const {
    reader_(i, j_begin, j_end, out);
  }
  // score(i, j): the cell reader when there is one, else a row segment of one cell.
  Score at(std::size_t i, std::size_t j) const;
  const CellReader& cell_reader() const { return cell_; }
  // Whether a row segment is read from memory (a dense matrix, or one derived from it) rather than computed: a
  // caller that would copy the scores to read them more than once can read them where they are.
  bool in_memory() const { return in_memory_; }

 private:
  std::size_t rows_;
  std::size_t cols_;
  RowReader reader_;
  CellReader cell_;
  bool in_memory_ = false;
};

}  // namespace seqtopo::align
