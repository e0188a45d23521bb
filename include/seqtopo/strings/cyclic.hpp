#pragma once
// Cyclic variants for panoramic fingerprints: a panorama starts wherever the robot happened to face, so
// the text T (a database string) is a circular string and the pattern P is compared with every rotation
// rotate(T, r) = T[r, m) + T[0, r). A and C report the best rotation offset r (the smallest on ties), B the
// rotation that puts its best occurrence first. All three are exact - they return what trying every
// rotation would - and usually cost a fraction of that (B always: one pass).
//
// A: branch and bound over the rotations. Rotations are tried in order; the banded DP of a rotation is
//    abandoned at the first row where every band cell, plus a lower bound of the cost still to come
//    (the remaining indels, diagonal steps at the cheapest diagonal cost), exceeds the best cost found
//    so far. The best is seeded with the unrotated text, so poor rotations die after a few rows.
// B: the text is doubled: occurrences of P in T + T[0, m - 1) are the occurrences in circular T (those
//    no longer than m, which covers every occurrence with <= k differences when n + k <= m). One
//    Landau-Vishkin pass instead of m.
// C: rotate(T, r) = T[r, m) + T[0, r), so LCS(P, T[r, m)) + LCS(P, T[0, r)) bounds its LCS from above.
//    Two passes of the cover construction (forwards, and on the reversed strings) give that bound for
//    every r at the cost of one LCS; rotations are then solved by Hunt-Szymanski in decreasing order of
//    the bound until the bound falls below the best length found.
#include <cstddef>
#include <string>
#include <string_view>

#include "seqtopo/strings/banded_global_alignment.hpp"
#include "seqtopo/strings/k_differences.hpp"
#include "seqtopo/strings/lcs_by_lis.hpp"

namespace seqtopo::strings {

std::string rotate(std::string_view text, std::size_t r);  // T[r, m) + T[0, r); r < m (or m == 0)

struct CyclicGlobalAlignment {
  GlobalAlignment alignment;  // of P against rotate(T, rotation)
  std::size_t rotation = 0;
};
// Best rotation: within k first, then lowest cost, then fewest differences.
CyclicGlobalAlignment cyclic_banded_global_alignment(std::string_view pattern, std::string_view text,
                                                     const GlobalAlignmentConfig& config = {});

struct CyclicKDifferencesResult {
  // Occurrences in circular T: end in [1, m] (exclusive end, read cyclically), fewest differences there.
  std::vector<Occurrence> occurrences;
  std::optional<std::size_t> best_differences() const;
  // Rotation that puts the best occurrence's approximate start (end - n, cyclically) first.
  std::size_t rotation = 0;
};
CyclicKDifferencesResult cyclic_k_differences(std::string_view pattern, std::string_view text,
                                              const KDifferencesConfig& config = {});

struct CyclicCommonSubsequence {
  CommonSubsequence lcs;  // pairs index rotate(T, rotation)
  std::size_t rotation = 0;
};
CyclicCommonSubsequence cyclic_lcs_by_lis(std::string_view pattern, std::string_view text);

}  // namespace seqtopo::strings
