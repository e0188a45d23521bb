#include "masked_frames.hpp"

#include <algorithm>
#include <cmath>

namespace seqtopo::mapping::detail {

align::ScoreSource soft_masked(const align::ScoreSource& scores, const std::vector<bool>& masked) {
  if (std::find(masked.begin(), masked.end(), true) == masked.end()) return scores;
  std::vector<std::size_t> frames;  // the masked ones, ascending: a row visits only those in its segment
  for (std::size_t f = 0; f < masked.size(); ++f) {
    if (masked[f]) frames.push_back(f);
  }
  return scores.derived(
      [scores, masked, frames](std::size_t i, std::size_t b, std::size_t e, align::Score* out) {
        scores.read_row(i, b, e, out);
        if (masked[i]) {
          for (std::size_t k = 0; k < e - b; ++k) out[k] = std::min(out[k], 0.0F);
          return;
        }
        for (auto f = std::lower_bound(frames.begin(), frames.end(), b); f != frames.end() && *f < e; ++f) {
          out[*f - b] = std::min(out[*f - b], 0.0F);
        }
      },
      [scores, masked](std::size_t i, std::size_t j) {
        const align::Score v = scores.at(i, j);
        return masked[i] || masked[j] ? std::min(v, 0.0F) : v;
      });
}

void soft_mask(SimilarityMatrix& enhanced, const std::vector<bool>& masked, float ceiling) {
  if (masked.empty()) return;
  const std::size_t n = enhanced.rows;
  for (std::size_t i = 0; i < n; ++i) {
    float* row = enhanced.values.data() + i * enhanced.cols;
    if (masked[i]) {
      for (std::size_t j = 0; j < enhanced.cols; ++j) row[j] = std::min(row[j], ceiling);
      continue;
    }
    for (std::size_t j = 0; j < enhanced.cols; ++j) {
      if (masked[j]) row[j] = std::min(row[j], ceiling);
    }
  }
}

std::vector<std::size_t> through_masked_frames(std::vector<align::LocalAlignment>& alignments,
                                               const std::vector<bool>& masked) {
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    auto& a = alignments[k];
    const auto evidence = [&](const std::pair<std::size_t, std::size_t>& p) {
      return !masked[p.first] && !masked[p.second];
    };
    std::vector<std::size_t> at;  // indices of the pairs with evidence
    for (std::size_t t = 0; t < a.pairs.size(); ++t) {
      if (evidence(a.pairs[t])) at.push_back(t);
    }
    if (at.empty()) continue;
    kept.push_back(k);
    if (at.size() == a.pairs.size()) continue;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t u = 0; u < at.size(); ++u) {
      const auto [i0, j0] = a.pairs[at[u]];
      pairs.emplace_back(i0, j0);
      if (u + 1 == at.size() || at[u + 1] == at[u] + 1) continue;
      // Masked pairs between two pairs of evidence: as many steps as both sides allow, evenly spaced.
      const auto [i1, j1] = a.pairs[at[u + 1]];
      const double di = static_cast<double>(i1) - static_cast<double>(i0);
      const double dj = static_cast<double>(j1) - static_cast<double>(j0);
      const auto steps = static_cast<std::size_t>(std::min(std::abs(di), std::abs(dj)));
      for (std::size_t t = 1; t < steps; ++t) {
        const double f = static_cast<double>(t) / static_cast<double>(steps);
        pairs.emplace_back(static_cast<std::size_t>(std::llround(static_cast<double>(i0) + f * di)),
                           static_cast<std::size_t>(std::llround(static_cast<double>(j0) + f * dj)));
      }
    }
    a.pairs = std::move(pairs);
    a = align::pairs_between(a, 0, a.pairs.size() - 1);
  }
  return kept;
}

void posteriors_through_masked(const align::LocalAlignment& a, const std::vector<bool>& masked, std::size_t tolerance,
                               std::vector<double>& posteriors) {
  const auto evidence = [&](std::size_t t) { return !masked[a.pairs[t].first] && !masked[a.pairs[t].second]; };
  for (std::size_t t = 0; t < a.pairs.size();) {
    if (evidence(t)) {
      ++t;
      continue;
    }
    std::size_t u = t;
    while (u < a.pairs.size() && !evidence(u)) ++u;
    // Pairs [t, u) between evidence t - 1 and u (through_masked_frames cut the ends, so both exist).
    if (t > 0 && u < a.pairs.size()) {
      const auto [i0, j0] = a.pairs[t - 1];
      const auto [i1, j1] = a.pairs[u];
      const double di = static_cast<double>(i1) - static_cast<double>(i0);
      const double dj = std::abs(static_cast<double>(j1) - static_cast<double>(j0));
      const double spread = std::min(1.0, (2.0 * static_cast<double>(tolerance) + 1) / (std::abs(di - dj) + 1));
      const double sure = std::min(posteriors[t - 1], posteriors[u]) * spread;
      for (std::size_t k = t; k < u; ++k) posteriors[k] = sure;
    }
    t = u;
  }
}

}  // namespace seqtopo::mapping::detail
