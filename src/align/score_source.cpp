#include "seqtopo/align/score_source.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace seqtopo::align {
namespace {

template <typename T>
ScoreSource dense_source(std::span<const T> values, std::size_t rows, std::size_t cols) {
  if (values.size() != rows * cols) {
    throw std::invalid_argument("score matrix has " + std::to_string(values.size()) + " values, expected " +
                                std::to_string(rows) + " x " + std::to_string(cols));
  }
  return ScoreSource(rows, cols, [values, cols](std::size_t i, std::size_t j_begin, std::size_t j_end, Score* out) {
    const T* row = values.data() + i * cols;
    std::transform(row + j_begin, row + j_end, out, [](T v) { return static_cast<Score>(v); });
  });
}

}  // namespace

ScoreSource::ScoreSource(std::size_t rows, std::size_t cols, RowReader reader, CellReader cell)
    : rows_(rows), cols_(cols), reader_(std::move(reader)), cell_(std::move(cell)) {
  if (!reader_) throw std::invalid_argument("score source needs a row reader");
}

ScoreSource ScoreSource::dense(std::span<const float> values, std::size_t rows, std::size_t cols) {
  ScoreSource source = dense_source(values, rows, cols);
  source.in_memory_ = true;
  return source;
}

ScoreSource ScoreSource::dense(std::span<const double> values, std::size_t rows, std::size_t cols) {
  ScoreSource source = dense_source(values, rows, cols);
  source.in_memory_ = true;
  return source;
}

ScoreSource ScoreSource::derived(RowReader reader, CellReader cell) const {
  ScoreSource source(rows_, cols_, std::move(reader), std::move(cell));
  source.in_memory_ = in_memory_;
  return source;
}

ScoreSource ScoreSource::subset(std::vector<std::size_t> frames) const {
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (frames[k] >= rows_ || frames[k] >= cols_ || (k > 0 && frames[k] <= frames[k - 1])) {
      throw std::invalid_argument("score source subset: frames must ascend within the source");
    }
  }
  const std::size_t n = frames.size();
  auto shared = std::make_shared<const std::vector<std::size_t>>(std::move(frames));
  ScoreSource source(
      n, n,
      [base = *this, shared](std::size_t i, std::size_t b, std::size_t e, Score* out) {
        if (b >= e) return;
        const auto& f = *shared;
        const std::size_t first = f[b], last = f[e - 1];
        if (last - first == e - b - 1) {  // no frame left out between them: one segment as it is
          base.read_row(f[i], first, last + 1, out);
          return;
        }
        std::vector<Score> row(last - first + 1);
        base.read_row(f[i], first, last + 1, row.data());
        for (std::size_t k = b; k < e; ++k) *out++ = row[f[k] - first];
      },
      [base = *this, shared](std::size_t i, std::size_t j) { return base.at((*shared)[i], (*shared)[j]); });
  source.in_memory_ = in_memory_;
  return source;
}

ScoreSource ScoreSource::function(std::size_t rows, std::size_t cols,
                                  std::function<Score(std::size_t, std::size_t)> score) {
  if (!score) throw std::invalid_argument("score source needs a score function");
  return ScoreSource(rows, cols,
                     [score = std::move(score)](std::size_t i, std::size_t j_begin, std::size_t j_end, Score* out) {
                       for (std::size_t j = j_begin; j < j_end; ++j) *out++ = score(i, j);
                     });
}

Score ScoreSource::at(std::size_t i, std::size_t j) const {
  if (cell_) return cell_(i, j);
  Score s = 0;
  reader_(i, j, j + 1, &s);
  return s;
}

}  // namespace seqtopo::align
