#pragma once
// Algorithm A of the localization paper: global alignment of a pattern P (length n) with a text T
// (length m) using at most k differences, by dynamic programming restricted to a band of diagonals.
//
// D(i, j) is the cost of turning P[0, i) into T[0, j):
//   D(i, j) = min( D(i-1, j) + deletion, D(i, j-1) + insertion, D(i-1, j-1) + costs.substitution(p_i, t_j) ),
//   D(i, 0) = i * deletion, D(0, j) = j * insertion.
// A "difference" is any step other than a coincidence (equal symbols on the diagonal). An alignment with
// at most k differences uses at most k indels, so it never leaves the diagonals d = j - i with
// |d| + |d - (m - n)| <= k (Ukkonen's band, about k + 1 diagonals wide): only those cells are filled,
// O(k * n) time and space.
//
// The result is the cheapest alignment inside the band (ties: fewer differences). `within_k` says whether
// it uses at most k differences. With unit costs this is exact: within_k <=> edit distance <= k, and then
// cost == differences == the edit distance. With weighted costs the band is the paper's restriction and
// the cheapest banded alignment is reported even when a dearer one would need fewer differences.
//
// Example (unit costs): P = "vAvB", T = "vAvvB", k = 1 -> within_k, cost 1, path "==I==".
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

#include "seqtopo/strings/costs.hpp"

namespace seqtopo::strings {

inline constexpr std::size_t kNoLimit = std::numeric_limits<std::size_t>::max();

struct GlobalAlignmentConfig {
  std::size_t k = kNoLimit;  // maximum number of differences; kNoLimit fills the whole table
  EditCosts costs{};
  bool want_path = false;  // also return the edit path (traceback, O(n + m))
};

struct GlobalAlignment {
  bool within_k = false;  // false: "more than k differences" (cost/differences then meaningless)
  double cost = std::numeric_limits<double>::infinity();
  std::size_t differences = 0;  // non-coincidence steps of the reported alignment
  // One letter per step, P against T: '=' coincidence, 'X' substitution, 'D' deletion (P symbol
  // skipped), 'I' insertion (T symbol skipped). Empty unless asked for.
  std::string path;
};

// Throws std::invalid_argument for invalid costs (see validate()).
GlobalAlignment banded_global_alignment(std::string_view pattern, std::string_view text,
                                        const GlobalAlignmentConfig& config = {});

namespace detail {
// As above, but gives up (returns within_k = false, cost = +inf) as soon as every band cell of a row
// provably leads to a cost above `abandon_above`; the cyclic variant uses it for branch and bound.
GlobalAlignment banded_global_alignment_bounded(std::string_view pattern, std::string_view text,
                                                const GlobalAlignmentConfig& config, double abandon_above);
}  // namespace detail

}  // namespace seqtopo::strings
