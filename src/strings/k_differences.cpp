#include "seqtopo/strings/k_differences.hpp"

#include <algorithm>
#include <cstdint>

#include "seqtopo/strings/longest_common_extension.hpp"

namespace seqtopo::strings {

std::optional<std::size_t> KDifferencesResult::best_differences() const {
  if (occurrences.empty()) return std::nullopt;
  return std::min_element(occurrences.begin(), occurrences.end(),
                          [](const Occurrence& a, const Occurrence& b) { return a.differences < b.differences; })
      ->differences;
}

KDifferencesResult k_differences(std::string_view pattern, std::string_view text, const KDifferencesConfig& config) {
  using Index = std::int64_t;
  const Index n = static_cast<Index>(pattern.size()), m = static_cast<Index>(text.size());
  // More than n differences are never needed (delete all of P), so larger k changes nothing.
  const Index k = static_cast<Index>(std::min<std::size_t>(config.k, pattern.size()));
  const LongestCommonExtension lce(pattern, text);
  constexpr Index kUnreached = -1;

  // Row reached on each diagonal d in [-k - 1, m + 1] (one spare on each side), for e - 1 and e.
  const Index first = -k - 1, count = m + k + 3;
  std::vector<Index> prev(static_cast<std::size_t>(count), kUnreached), cur(prev);
  auto slot = [&](Index d) { return static_cast<std::size_t>(d - first); };
  std::vector<std::size_t> found(static_cast<std::size_t>(m + 1), static_cast<std::size_t>(-1));

  auto extend = [&](Index d, Index row) {
    if (row < n && row + d < m)
      row += static_cast<Index>(lce(static_cast<std::size_t>(row), static_cast<std::size_t>(row + d)));
    return row;
  };
  for (Index e = 0; e <= k; ++e) {
    for (Index d = -e; d <= m; ++d) {
      const Index max_row = std::min(n, m - d);
      Index row = kUnreached;
      if (e == 0) {
        if (d >= 0) row = 0;  // a path may start anywhere on row 0
      } else {
        // Candidates past the table's edge are clamped: D never decreases along a diagonal, so every
        // cell before the furthest one reached with e - 1 differences is reachable with e - 1 too.
        const Index same = prev[slot(d)];
        if (same != kUnreached) row = std::max(row, same + 1);  // substitution
        const Index below = prev[slot(d + 1)];
        if (below != kUnreached) row = std::max(row, below + 1);  // delete a P symbol
        const Index above = prev[slot(d - 1)];
        if (above != kUnreached) row = std::max(row, above);  // insert a T symbol
        if (row != kUnreached) row = std::min(row, max_row);
      }
      if (row == kUnreached || row < -d) {
        cur[slot(d)] = kUnreached;
        continue;
      }
      row = extend(d, std::min(row, max_row));
      cur[slot(d)] = row;
      const std::size_t end = static_cast<std::size_t>(row + d);
      if (row == n && found[end] == static_cast<std::size_t>(-1)) found[end] = static_cast<std::size_t>(e);
    }
    prev.swap(cur);
    std::fill(cur.begin(), cur.end(), kUnreached);
  }
  KDifferencesResult result;
  for (Index j = 0; j <= m; ++j) {
    if (found[static_cast<std::size_t>(j)] != static_cast<std::size_t>(-1)) {
      result.occurrences.push_back({static_cast<std::size_t>(j), found[static_cast<std::size_t>(j)]});
    }
  }
  return result;
}

}  // namespace seqtopo::strings
