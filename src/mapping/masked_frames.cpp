#include "masked_frames.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace seqtopo::mapping::detail {
namespace {
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

// The half-open ranges spanning the pairs again (kept as they were when there is none).
void span_pairs(align::LocalAlignment& a) {
  if (!a.pairs.empty()) a = align::pairs_between(a, 0, a.pairs.size() - 1);
}
}  // namespace

UnmaskedFrames::UnmaskedFrames(std::size_t frames, const std::vector<bool>& left_out) {
  if (!left_out.empty() && left_out.size() != frames)
    throw std::invalid_argument("frames left out: one flag per frame");
  index_.assign(frames, kNone);
  for (std::size_t f = 0; f < frames; ++f) {
    if (!left_out.empty() && left_out[f]) {
      any_ = true;
      continue;
    }
    index_[f] = frames_.size();
    frames_.push_back(f);
  }
}

std::vector<bool> UnmaskedFrames::of_view(const std::vector<bool>& flags) const {
  if (!any_ || flags.empty()) return flags;
  std::vector<bool> out(frames_.size());
  for (std::size_t k = 0; k < frames_.size(); ++k) out[k] = flags[frames_[k]];
  return out;
}

std::vector<std::size_t> flagged_frames(const std::vector<bool>& flags) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < flags.size(); ++k) {
    if (flags[k]) out.push_back(k);
  }
  return out;
}

std::vector<bool> long_stretches(const std::vector<bool>& flags, std::size_t min_length) {
  std::vector<bool> out(flags.size(), false);
  bool any = false;
  for (std::size_t f = 0; f < flags.size();) {
    if (!flags[f]) {
      ++f;
      continue;
    }
    std::size_t end = f;
    while (end < flags.size() && flags[end]) ++end;
    if (end - f >= min_length) {
      for (std::size_t k = f; k < end; ++k) out[k] = true;
      any = true;
    }
    f = end;
  }
  return any ? out : std::vector<bool>{};
}

align::ScoreSource UnmaskedFrames::view(const align::ScoreSource& full) const {
  return any_ ? full.subset(frames_) : full;
}

align::LocalAlignment UnmaskedFrames::to_frames(align::LocalAlignment a) const {
  if (!any_) return a;
  for (auto& [i, j] : a.pairs) {
    i = frames_[i];
    j = frames_[j];
  }
  if (!a.pairs.empty()) {
    span_pairs(a);
  } else if (a.a_end > a.a_begin && a.b_end > a.b_begin) {
    a.a_begin = frames_[a.a_begin];
    a.a_end = frames_[a.a_end - 1] + 1;
    a.b_begin = frames_[a.b_begin];
    a.b_end = frames_[a.b_end - 1] + 1;
  }
  return a;
}

align::LocalAlignment UnmaskedFrames::to_unmasked(const align::LocalAlignment& a) const {
  if (!any_) return a;
  align::LocalAlignment out = a;
  out.pairs.clear();
  for (const auto& [i, j] : a.pairs) {
    if (index_[i] != kNone && index_[j] != kNone) out.pairs.emplace_back(index_[i], index_[j]);
  }
  span_pairs(out);
  return out;
}

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
    // Whether both passes skip frames between consecutive pairs of evidence u and u + 1, masked ones in at least one
    // of them (a step of the alignment over a stretch left out of it, UnmaskedFrames), or masked pairs between them.
    const auto masked_between = [&](std::size_t x, std::size_t y) {
      for (std::size_t f = std::min(x, y) + 1; f < std::max(x, y); ++f) {
        if (masked[f]) return true;
      }
      return false;
    };
    const auto skips = [](std::size_t x, std::size_t y) { return std::max(x, y) - std::min(x, y) > 1; };
    std::vector<bool> crosses(at.size(), false);
    bool any = at.size() != a.pairs.size();
    for (std::size_t u = 0; u + 1 < at.size(); ++u) {
      const auto [i0, j0] = a.pairs[at[u]];
      const auto [i1, j1] = a.pairs[at[u + 1]];
      crosses[u] = at[u + 1] != at[u] + 1 ||
                   (skips(i0, i1) && skips(j0, j1) && (masked_between(i0, i1) || masked_between(j0, j1)));
      any = any || crosses[u];
    }
    if (!any) continue;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t u = 0; u < at.size(); ++u) {
      const auto [i0, j0] = a.pairs[at[u]];
      pairs.emplace_back(i0, j0);
      if (!crosses[u]) continue;
      // Masked frames between two pairs of evidence: as many steps as both sides allow, evenly spaced.
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
