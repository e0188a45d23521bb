#include "seqtopo/strings/lcs_by_lis.hpp"

#include <algorithm>
#include <array>

namespace seqtopo::strings {

std::vector<std::size_t> longest_increasing_subsequence(const std::vector<std::size_t>& values) {
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> last;        // index (into values) of the last number of each cover subsequence
  std::vector<std::size_t> last_value;  // values[last[s]], increasing in s
  std::vector<std::size_t> back(values.size(), kNone);
  for (std::size_t i = 0; i < values.size(); ++i) {
    // First subsequence whose last number is >= values[i]: appending keeps it non-increasing.
    const auto it = std::lower_bound(last_value.begin(), last_value.end(), values[i]);
    const auto s = static_cast<std::size_t>(it - last_value.begin());
    back[i] = s == 0 ? kNone : last[s - 1];
    if (it == last_value.end()) {
      last.push_back(i);
      last_value.push_back(values[i]);
    } else {
      last[s] = i;
      *it = values[i];
    }
  }
  std::vector<std::size_t> lis;
  for (std::size_t i = last.empty() ? kNone : last.back(); i != kNone; i = back[i]) lis.push_back(i);
  std::reverse(lis.begin(), lis.end());
  return lis;
}

CommonSubsequence lcs_by_lis(std::string_view pattern, std::string_view text) {
  std::array<std::vector<std::size_t>, 256> positions;  // positions in P of each symbol, decreasing
  for (std::size_t i = pattern.size(); i-- > 0;) positions[static_cast<unsigned char>(pattern[i])].push_back(i);
  std::vector<std::size_t> pi, pi_text;
  for (std::size_t j = 0; j < text.size(); ++j) {
    for (std::size_t i : positions[static_cast<unsigned char>(text[j])]) {
      pi.push_back(i);
      pi_text.push_back(j);
    }
  }
  CommonSubsequence result;
  for (std::size_t index : longest_increasing_subsequence(pi)) {
    result.pairs.emplace_back(pi[index], pi_text[index]);
    result.symbols.push_back(pattern[pi[index]]);
  }
  result.length = result.pairs.size();
  return result;
}

}  // namespace seqtopo::strings
