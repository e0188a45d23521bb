#pragma once
// One new row of a capped Smith-Waterman table from the previous one, as a sequence that grows by one frame at a
// time needs it: the online mapper's self search (mapping/online_mapper.hpp) and the online localizer's search
// of a map (localize/online_localizer.hpp). Forward rows read the diagonal at j - 1 and fill left to right;
// reverse rows (a path revisited the other way round) read the diagonal at j + 1 and fill right to left. Each
// cell is capped_cell (capped_cell.hpp), so a row is the same bits as the offline engine's row of the same
// scores. The previous row may be shorter than the new one (a self search's table grows by a column a frame):
// its missing cells are 0, as are neighbours outside the row.
#include <cstddef>
#include <optional>
#include <span>

#include "seqtopo/align/capped_cell.hpp"

namespace seqtopo::align {

inline constexpr std::size_t kNoCell = static_cast<std::size_t>(-1);

// The step that gives a cell its value: the first of diagonal, up, left (the engine's order) that attains it; none
// for a cell at 0. A local alignment ends on a matched pair, so a cell is an alignment's end when its step is
// diagonal.
enum class Step { none, diagonal, up, left };

// Fills row[j] for every j < row.size() from `previous` and scores[j] (scores.size() >= row.size()), and calls
// visit(j, step, diagonal_at, left_at) after each cell: the step that gave its value, the index in `previous` of the
// diagonal predecessor and the index in `row` of the left one (kNoCell outside), for callers that follow the paths.
template <class Visit>
void fill_online_row(std::span<const float> previous, std::span<const float> scores, std::span<float> row, bool reverse,
                     float gap, const std::optional<float>& cap, Visit&& visit) {
  const std::size_t n = row.size(), m = previous.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = reverse ? n - 1 - k : k;
    const std::size_t diagonal_at = reverse ? (j + 1 < m ? j + 1 : kNoCell) : (j > 0 && j - 1 < m ? j - 1 : kNoCell);
    const std::size_t left_at = reverse ? (j + 1 < n ? j + 1 : kNoCell) : (j > 0 ? j - 1 : kNoCell);
    const float diagonal = diagonal_at != kNoCell ? previous[diagonal_at] : 0.0F;
    const float up = j < m ? previous[j] : 0.0F;
    const float left = left_at != kNoCell ? row[left_at] : 0.0F;
    const float step = diagonal + scores[j];
    const float v = row[j] = capped_cell(step, up, left, gap, gap, cap);
    const Step attained = !(v > 0)                     ? Step::none
                          : capped(step, cap) == v     ? Step::diagonal
                          : capped(up - gap, cap) == v ? Step::up
                                                       : Step::left;
    visit(j, attained, diagonal_at, left_at);
  }
}

inline void fill_online_row(std::span<const float> previous, std::span<const float> scores, std::span<float> row,
                            bool reverse, float gap, const std::optional<float>& cap) {
  fill_online_row(previous, scores, row, reverse, gap, cap, [](std::size_t, Step, std::size_t, std::size_t) {});
}

}  // namespace seqtopo::align
