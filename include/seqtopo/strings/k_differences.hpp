#pragma once
// Algorithm B of the localization paper: k-differences inexact matching. Finds every end position in
// the text T (length m) of a substring that matches the pattern P (length n) with at most k differences
// (unit-cost substitutions, insertions, deletions) - the "infix" edit distance.
//
// Landau-Vishkin: in the dynamic programming table (rows = P, columns = T), diagonal d = column - row
// holds cells (r, r + d); a path may start anywhere on row 0. For e = 0..k and every diagonal
// d in [-k, m], L[d][e] = the furthest row any path with e differences reaches on diagonal d. It comes
// from the (e-1)-paths on diagonals d (substitution), d + 1 (deletion of a P symbol) and d - 1 (insertion
// of a T symbol), followed by the longest run of equal symbols, which a constant-time longest common
// extension query gives. L[d][e] = n means an occurrence ending at column n + d with e differences.
// O(k * m) queries after O((n + m) log(n + m)) preprocessing.
//
// Example: P = "vAB", T = "CCvABvAAB", k = 1 -> end 5 (0 differences) and ends 4, 6, 7, 8, 9 (1 each).
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace seqtopo::strings {

struct KDifferencesConfig {
  std::size_t k = 0;
};

struct Occurrence {
  std::size_t end = 0;          // exclusive end position in T
  std::size_t differences = 0;  // fewest differences of a match of P ending there
};

struct KDifferencesResult {
  std::vector<Occurrence> occurrences;  // every end with <= k differences, increasing end; empty: none
  std::optional<std::size_t> best_differences() const;
};

KDifferencesResult k_differences(std::string_view pattern, std::string_view text,
                                 const KDifferencesConfig& config = {});

}  // namespace seqtopo::strings
