#pragma once
// Longest common extension of two strings a and b: lce(i, j) = length of the longest common prefix of
// a[i..] and b[j..], in O(1) per query after O(N log N) preprocessing (N = |a| + |b|).
//
// a and b are joined with a separator into one sequence; its suffix array (prefix doubling), the LCP
// array (Kasai et al.) and a sparse table of LCP minima answer a query as the minimum LCP between the
// two suffixes' ranks. This stands in for the generalized suffix tree of Landau-Vishkin's algorithm.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace seqtopo::strings {

class LongestCommonExtension {
 public:
  LongestCommonExtension(std::string_view a, std::string_view b);
  // i <= |a|, j <= |b|; throws std::out_of_range otherwise.
  std::size_t operator()(std::size_t i, std::size_t j) const;

 private:
  std::size_t a_size_ = 0, b_size_ = 0;
  std::vector<std::uint32_t> rank_;              // rank of each suffix of the joined sequence
  std::vector<std::vector<std::uint32_t>> min_;  // min_[p][r] = min LCP over ranks [r, r + 2^p)
};

// Suffix array of a sequence of integer symbols (prefix doubling); exposed for tests.
std::vector<std::uint32_t> suffix_array(const std::vector<std::uint32_t>& symbols);

}  // namespace seqtopo::strings
