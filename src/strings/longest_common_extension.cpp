#include "seqtopo/strings/longest_common_extension.hpp"

#include <algorithm>
#include <bit>
#include <numeric>
#include <stdexcept>

namespace seqtopo::strings {

std::vector<std::uint32_t> suffix_array(const std::vector<std::uint32_t>& s) {
  const std::size_t n = s.size();
  std::vector<std::uint32_t> sa(n), rank(s.begin(), s.end()), next(n);
  std::iota(sa.begin(), sa.end(), 0U);
  if (n <= 1) return sa;
  // Sort by (rank[i], rank[i + h]) for doubling h; a missing second half sorts first.
  for (std::size_t h = 1;; h *= 2) {
    auto key = [&](std::uint32_t i) {
      const std::int64_t second = i + h < n ? static_cast<std::int64_t>(rank[i + h]) : -1;
      return std::pair<std::int64_t, std::int64_t>(rank[i], second);
    };
    std::sort(sa.begin(), sa.end(), [&](std::uint32_t x, std::uint32_t y) { return key(x) < key(y); });
    next[sa[0]] = 0;
    for (std::size_t r = 1; r < n; ++r) next[sa[r]] = next[sa[r - 1]] + (key(sa[r - 1]) < key(sa[r]) ? 1 : 0);
    rank.swap(next);
    if (rank[sa[n - 1]] == n - 1) break;  // all suffixes distinct
  }
  return sa;
}

LongestCommonExtension::LongestCommonExtension(std::string_view a, std::string_view b)
    : a_size_(a.size()), b_size_(b.size()) {
  // Symbols 1..256 for bytes; 257 separates a from b and 0 ends b, so no common prefix crosses either.
  std::vector<std::uint32_t> s;
  s.reserve(a.size() + b.size() + 2);
  for (unsigned char ch : a) s.push_back(1U + ch);
  s.push_back(257U);
  for (unsigned char ch : b) s.push_back(1U + ch);
  s.push_back(0U);
  const std::size_t n = s.size();
  const auto sa = suffix_array(s);
  rank_.assign(n, 0);
  for (std::size_t r = 0; r < n; ++r) rank_[sa[r]] = static_cast<std::uint32_t>(r);
  // Kasai: lcp[r] = LCP(suffix sa[r - 1], suffix sa[r]).
  std::vector<std::uint32_t> lcp(n, 0);
  std::size_t h = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rank_[i] == 0) {
      h = 0;
      continue;
    }
    const std::size_t j = sa[rank_[i] - 1];
    while (i + h < n && j + h < n && s[i + h] == s[j + h]) ++h;
    lcp[rank_[i]] = static_cast<std::uint32_t>(h);
    if (h > 0) --h;
  }
  min_.push_back(std::move(lcp));
  for (std::size_t p = 1; (std::size_t{1} << p) <= n; ++p) {
    const auto& prev = min_.back();
    const std::size_t half = std::size_t{1} << (p - 1);
    std::vector<std::uint32_t> level(n - (std::size_t{1} << p) + 1);
    for (std::size_t r = 0; r < level.size(); ++r) level[r] = std::min(prev[r], prev[r + half]);
    min_.push_back(std::move(level));
  }
}

std::size_t LongestCommonExtension::operator()(std::size_t i, std::size_t j) const {
  if (i > a_size_ || j > b_size_) throw std::out_of_range("longest common extension: position past the end");
  if (i == a_size_ || j == b_size_) return 0;
  std::size_t x = rank_[i], y = rank_[a_size_ + 1 + j];
  if (x > y) std::swap(x, y);
  // Minimum of lcp over ranks (x, y].
  const std::size_t len = y - x;
  const std::size_t p = static_cast<std::size_t>(std::bit_width(len)) - 1;
  return std::min(min_[p][x + 1], min_[p][y + 1 - (std::size_t{1} << p)]);
}

}  // namespace seqtopo::strings
