#pragma once
// The far end of a capped plateau, shared by every engine so that they all end an alignment at the same
// cell: the last maximal cell (row-major) reachable from `first` by tight steps.
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace seqtopo::align::detail {

// Rows are visited downwards from first.first, each once, so an engine that streams its rows can follow.
// `grid` answers, in pass coordinates (1-based):
//   top(i, j)   the cell holds the plateau's value;
//   right(i, j) the step into (i, j) from (i, j-1) is tight;
//   next_row()  row i is done, row i+1 is about to be read (called before down/diag of row i+1);
//   down(i, j), diag(i, j)  the step into (i, j) from above / from (i-1, j-1) is tight.
template <typename Grid>
std::pair<std::size_t, std::size_t> plateau_far_end(std::pair<std::size_t, std::size_t> first, std::size_t rows,
                                                    std::size_t cols, Grid&& grid) {
  auto end = first;
  std::vector<std::size_t> seeds{first.second}, closed;
  for (std::size_t i = first.first; !seeds.empty(); ++i) {
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    closed.clear();
    for (std::size_t j : seeds) {  // close the row under rightward tight steps
      if (!closed.empty() && j <= closed.back()) continue;
      closed.push_back(j);
      while (j < cols && grid.right(i, j + 1)) closed.push_back(++j);
    }
    seeds.clear();
    for (std::size_t j : closed) {
      if (grid.top(i, j)) end = {i, j};
    }
    if (i == rows) break;
    grid.next_row();
    for (std::size_t j : closed) {
      if (grid.down(i + 1, j)) seeds.push_back(j);
      if (j < cols && grid.diag(i + 1, j + 1)) seeds.push_back(j + 1);
    }
  }
  return end;
}

}  // namespace seqtopo::align::detail
