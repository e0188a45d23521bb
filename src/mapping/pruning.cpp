#include "seqtopo/mapping/pruning.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace seqtopo::mapping {

PruningResult prune_per_column(const std::vector<align::LocalAlignment>& alignments, const PruningConfig& config) {
  if (!(config.min_retained_fraction >= 0.0 && config.min_retained_fraction <= 1.0)) {
    throw std::invalid_argument("min_retained_fraction must be in [0, 1]");
  }
  std::size_t columns = 0;
  for (const auto& a : alignments) columns = std::max(columns, a.b_end);

  // Winner of each column: index of the best covering alignment.
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> winner(columns, kNone);
  auto better = [&](std::size_t x, std::size_t y) {  // is alignment x better than y?
    const auto& ax = alignments[x];
    const auto& ay = alignments[y];
    const bool longer = ax.pairs.size() > ay.pairs.size(), same_length = ax.pairs.size() == ay.pairs.size();
    if (config.rank == PruningConfig::Rank::score_then_length) {
      if (ax.score != ay.score) return ax.score > ay.score;
      if (!same_length) return longer;
    } else {
      if (!same_length) return longer;
      if (ax.score != ay.score) return ax.score > ay.score;
    }
    return x < y;
  };
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    for (std::size_t j = alignments[k].b_begin; j < alignments[k].b_end; ++j) {
      if (winner[j] == kNone || better(k, winner[j])) winner[j] = k;
    }
  }

  PruningResult result;
  result.kept.assign(alignments.size(), false);
  result.retained_count.assign(alignments.size(), 0);
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    for (auto [i, j] : alignments[k].pairs) result.retained_count[k] += winner[j] == k ? 1 : 0;
    const auto total = static_cast<double>(alignments[k].pairs.size());
    result.kept[k] = result.retained_count[k] > 0 &&
                     static_cast<double>(result.retained_count[k]) >= config.min_retained_fraction * total;
    if (!result.kept[k]) {
      result.retained_count[k] = 0;
      continue;
    }
    for (auto [i, j] : alignments[k].pairs) {
      if (winner[j] == k) result.pairs.push_back({i, j, k, alignments[k].score});
    }
  }
  return result;
}

std::map<std::size_t, std::pair<RetainedPair, RetainedPair>> retained_ends(const PruningResult& pruning) {
  std::map<std::size_t, std::pair<RetainedPair, RetainedPair>> ends;
  for (const auto& pair : pruning.pairs) {
    auto [it, fresh] = ends.try_emplace(pair.alignment, pair, pair);
    if (fresh) continue;
    if (pair.i < it->second.first.i) it->second.first = pair;
    if (pair.i > it->second.second.i) it->second.second = pair;
  }
  return ends;
}

}  // namespace seqtopo::mapping
