#include "seqtopo/strings/cyclic.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

namespace seqtopo::strings {

std::string rotate(std::string_view text, std::size_t r) {
  if (text.empty()) return {};
  if (r >= text.size()) throw std::invalid_argument("rotate: offset past the end of the string");
  std::string out(text.substr(r));
  out.append(text.substr(0, r));
  return out;
}

namespace {

// Ordering of rotations for algorithm A: within k, then cost, then differences.
bool better(const GlobalAlignment& a, const GlobalAlignment& b) {
  if (a.within_k != b.within_k) return a.within_k;
  if (!a.within_k) return false;
  return a.cost < b.cost || (a.cost == b.cost && a.differences < b.differences);
}

}  // namespace

CyclicGlobalAlignment cyclic_banded_global_alignment(std::string_view pattern, std::string_view text,
                                                     const GlobalAlignmentConfig& config) {
  CyclicGlobalAlignment best;
  GlobalAlignmentConfig quiet = config;
  quiet.want_path = false;
  best.alignment = banded_global_alignment(pattern, text, quiet);
  for (std::size_t r = 1; r < text.size(); ++r) {
    const double bound = best.alignment.within_k ? best.alignment.cost : std::numeric_limits<double>::infinity();
    const GlobalAlignment candidate = detail::banded_global_alignment_bounded(pattern, rotate(text, r), quiet, bound);
    if (better(candidate, best.alignment)) best = {candidate, r};
  }
  if (config.want_path && best.alignment.within_k) {
    best.alignment = banded_global_alignment(pattern, rotate(text, best.rotation), config);
  }
  return best;
}

std::optional<std::size_t> CyclicKDifferencesResult::best_differences() const {
  if (occurrences.empty()) return std::nullopt;
  return std::min_element(occurrences.begin(), occurrences.end(),
                          [](const Occurrence& a, const Occurrence& b) { return a.differences < b.differences; })
      ->differences;
}

CyclicKDifferencesResult cyclic_k_differences(std::string_view pattern, std::string_view text,
                                              const KDifferencesConfig& config) {
  CyclicKDifferencesResult result;
  const std::size_t m = text.size();
  if (m == 0) {
    const auto plain = k_differences(pattern, text, config);
    result.occurrences = plain.occurrences;
    return result;
  }
  std::string doubled(text);
  doubled.append(text.substr(0, m - 1));
  const auto plain = k_differences(pattern, doubled, config);
  // Ends e and e + m are the same circular position; keep the fewer differences.
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> fewest(m + 1, kNone);
  for (const Occurrence& o : plain.occurrences) {
    if (o.end == 0) continue;  // an empty match before the text: the same as end m
    const std::size_t c = (o.end - 1) % m + 1;
    fewest[c] = std::min(fewest[c], o.differences);
  }
  for (std::size_t c = 1; c <= m; ++c) {
    if (fewest[c] != kNone) result.occurrences.push_back({c, fewest[c]});
  }
  if (!plain.occurrences.empty() && plain.occurrences.front().end == 0 && fewest[m] == kNone) {
    result.occurrences.push_back({m, plain.occurrences.front().differences});
  }
  if (const auto best = result.best_differences()) {
    for (const Occurrence& o : result.occurrences) {
      if (o.differences == *best) {
        const std::size_t n_mod = pattern.size() % m;
        result.rotation = (o.end + m - n_mod) % m;
        break;
      }
    }
  }
  return result;
}

namespace {

// LCS(P, T[0, j)) for every j = 0..m, from one pass of the cover construction: the number of cover
// subsequences after the match lists of T[0, j) is the LIS of that part of Pi.
std::vector<std::size_t> prefix_lcs_lengths(std::string_view pattern, std::string_view text) {
  std::array<std::vector<std::size_t>, 256> positions;
  for (std::size_t i = pattern.size(); i-- > 0;) positions[static_cast<unsigned char>(pattern[i])].push_back(i);
  std::vector<std::size_t> last_value, lengths(1, 0);
  for (unsigned char c : text) {
    for (std::size_t i : positions[c]) {
      const auto it = std::lower_bound(last_value.begin(), last_value.end(), i);
      if (it == last_value.end()) {
        last_value.push_back(i);
      } else {
        *it = i;
      }
    }
    lengths.push_back(last_value.size());
  }
  return lengths;
}

}  // namespace

CyclicCommonSubsequence cyclic_lcs_by_lis(std::string_view pattern, std::string_view text) {
  const std::size_t m = text.size();
  if (m == 0) return {lcs_by_lis(pattern, text), 0};
  std::array<std::size_t, 256> in_pattern{}, in_text{};
  for (unsigned char c : pattern) ++in_pattern[c];
  for (unsigned char c : text) ++in_text[c];
  std::size_t count_bound = 0;
  for (std::size_t c = 0; c < 256; ++c) count_bound += std::min(in_pattern[c], in_text[c]);

  // rotate(T, r) = T[r, m) + T[0, r), so LCS(P, rotate(T, r)) <= LCS(P, T[r, m)) + LCS(P, T[0, r)).
  const auto prefix = prefix_lcs_lengths(pattern, text);
  const std::string reversed_pattern(pattern.rbegin(), pattern.rend()), reversed_text(text.rbegin(), text.rend());
  const auto suffix = prefix_lcs_lengths(reversed_pattern, reversed_text);  // suffix[m - r] = LCS(P, T[r, m))
  std::vector<std::pair<std::size_t, std::size_t>> order;                   // (upper bound, rotation)
  for (std::size_t r = 0; r < m; ++r) order.emplace_back(std::min(count_bound, prefix[r] + suffix[m - r]), r);
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });

  CyclicCommonSubsequence best;
  bool have = false;
  for (const auto& [bound, r] : order) {
    // Bounds only fall from here on; a rotation can still win if it may beat, or tie with a smaller offset.
    if (have && (bound < best.lcs.length || (bound == best.lcs.length && r > best.rotation))) {
      if (bound < best.lcs.length) break;
      continue;
    }
    CommonSubsequence lcs = lcs_by_lis(pattern, rotate(text, r));
    if (!have || lcs.length > best.lcs.length || (lcs.length == best.lcs.length && r < best.rotation)) {
      best = {std::move(lcs), r};
      have = true;
    }
  }
  return best;
}

}  // namespace seqtopo::strings
