#pragma once
// Algorithm C of the localization paper: longest common subsequence of P (length n) and T (length m)
// through the longest increasing subsequence (Hunt-Szymanski reduction).
//
// For each symbol of T in order, list the positions in P of that symbol in decreasing order; the
// concatenation Pi has r entries (r = number of matching pairs). An increasing subsequence of Pi uses
// each T position at most once (its list is decreasing) and P positions in increasing order, so a
// longest increasing subsequence of Pi is an LCS. The LIS comes from a minimum cover of Pi by
// non-increasing subsequences: each number goes onto the first subsequence whose last number is >= it
// (binary search over the last numbers, which increase from the first subsequence to the last); a
// back pointer to the last number of the previous subsequence lets the LIS be read back from the last
// subsequence. O((r + n + m) log n) time, O(r + n + m) space.
//
// Example: P = "vABvC", T = "AvBCv" -> length 3, e.g. "vBC" (P positions 0, 2, 4; T positions 1, 2, 3).
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace seqtopo::strings {

struct CommonSubsequence {
  std::size_t length = 0;
  std::string symbols;                                     // the subsequence itself
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (position in P, position in T), increasing
  // n + m - 2 * length: the edit distance with insertions and deletions only.
  std::size_t indel_distance(std::size_t n, std::size_t m) const { return n + m - 2 * length; }
};

CommonSubsequence lcs_by_lis(std::string_view pattern, std::string_view text);

// Longest strictly increasing subsequence of `values` by minimum cover; returns the indices into values.
std::vector<std::size_t> longest_increasing_subsequence(const std::vector<std::size_t>& values);

}  // namespace seqtopo::strings
