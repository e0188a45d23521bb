#include "step_box.hpp"

#include <algorithm>
#include <stdexcept>

namespace seqtopo::align::detail {

void StepBox::layout(BoxCell start, const std::vector<std::pair<std::size_t, std::size_t>>& spans, std::size_t rows) {
  r0 = start.first;
  c0 = start.second;
  lo.assign(rows, 0);
  hi.assign(rows, 0);
  offset.assign(rows, 0);
  std::size_t size = 1;  // row 0: the start alone
  for (std::size_t r = 1; r < rows; ++r) {
    const auto [first, last] = spans[rows - 1 - r];  // every row between start and end has such a cell
    lo[r] = std::max(first, c0 + 1) - c0;
    hi[r] = last - c0;
    offset[r] = size;
    size += hi[r] - lo[r] + 1;
  }
  steps.assign(size, 0);
  fwd.assign(size, 0);
  bwd.assign(size, 0);
}

void bisect(StepBox& box, BoxCell p, BoxCell q, std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  const std::size_t rows = q.first - p.first, cols = q.second - p.second;
  if (rows == 0 || cols == 0) return;
  if (rows == 1) {
    // suffix[k]: the rightward steps along row q.first after column p.second + k are all tight
    std::vector<std::uint8_t> suffix(cols + 1, 1);
    for (std::size_t k = cols; k-- > 0;) suffix[k] = suffix[k + 1] && box.right(q.first, p.second + k + 1);
    // A gap-only route (right along row p.first, down, right along row q.first) wins ties.
    bool prefix = true;  // the rightward steps along row p.first up to column p.second + k are tight
    for (std::size_t k = 0; k <= cols && prefix; ++k) {
      if (k > 0) prefix = box.right(p.first, p.second + k);
      if (prefix && box.down(q.first, p.second + k) && suffix[k]) return;
    }
    prefix = true;
    for (std::size_t k = 1; k <= cols && prefix; ++k) {
      if (box.diag(q.first, p.second + k) && suffix[k]) {
        pairs.emplace_back(q.first, p.second + k);
        return;
      }
      prefix = box.right(p.first, p.second + k);
    }
    throw std::logic_error("alignment bisection found no route");
  }
  const std::size_t mid = p.first + rows / 2;
  // fwd: reachable from p by tight steps (rows p.first .. mid); bwd: reaches q (rows mid .. q.first).
  // Each cell read below was written in this call or lies outside the band (reads 0).
  for (std::size_t r = p.first; r <= mid; ++r) {
    for (std::size_t c = std::max(p.second, box.lo[r]); c <= std::min(q.second, box.hi[r]); ++c) {
      const bool up = r > p.first, left = c > p.second;
      box.fwd[box.index(r, c)] =
          (r == p.first && c == p.second) || (up && left && box.diag(r, c) && box.f(r - 1, c - 1)) ||
          (up && box.down(r, c) && box.f(r - 1, c)) || (left && box.right(r, c) && box.f(r, c - 1));
    }
  }
  for (std::size_t r = q.first + 1; r-- > mid;) {
    const std::size_t c_lo = std::max(p.second, box.lo[r]), c_hi = std::min(q.second, box.hi[r]);
    for (std::size_t c = c_hi + 1; c-- > c_lo;) {
      const bool below = r < q.first, right = c < q.second;
      box.bwd[box.index(r, c)] =
          (r == q.first && c == q.second) || (below && right && box.diag(r + 1, c + 1) && box.b(r + 1, c + 1)) ||
          (below && box.down(r + 1, c) && box.b(r + 1, c)) || (right && box.right(r, c + 1) && box.b(r, c + 1));
    }
  }
  std::size_t cross = 0;
  bool found = false;
  for (std::size_t c = std::max(p.second, box.lo[mid]); c <= std::min(q.second, box.hi[mid]); ++c) {
    if (!box.f(mid, c) || !box.b(mid, c)) continue;
    const bool enters_down = box.down(mid, c) && box.f(mid - 1, c);
    const bool leaves_down = box.down(mid + 1, c) && box.b(mid + 1, c);
    if (!found || (!enters_down && leaves_down)) cross = c;
    found = true;
  }
  if (!found) throw std::logic_error("alignment bisection found no crossing");
  bisect(box, p, {mid, cross}, pairs);
  bisect(box, {mid, cross}, q, pairs);
}

LocalAlignment alignment_through(StepBox& box, BoxCell end, Direction direction, std::size_t n, Score score) {
  LocalAlignment a;
  a.direction = direction;
  a.score = score;
  bisect(box, {0, 0}, {end.first - box.r0, end.second - box.c0}, a.pairs);
  if (a.pairs.empty()) throw std::logic_error("alignment has no pair");
  for (auto& [r, c] : a.pairs) {
    const std::size_t i = box.r0 + r, j = box.c0 + c;
    r = i - 1;
    c = direction == Direction::forward ? j - 1 : n - j;
  }
  a.a_begin = a.pairs.front().first;
  a.a_end = a.pairs.back().first + 1;
  auto [b_min, b_max] = std::minmax_element(a.pairs.begin(), a.pairs.end(),
                                            [](const auto& x, const auto& y) { return x.second < y.second; });
  a.b_begin = b_min->second;
  a.b_end = b_max->second + 1;
  return a;
}

}  // namespace seqtopo::align::detail
