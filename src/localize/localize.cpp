#include "seqtopo/localize/localize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::localize {

namespace {

void check_matrix(const SimilarityMatrix& s) {
  if (s.empty()) throw std::invalid_argument("empty similarity matrix");
  if (s.values.size() != s.rows * s.cols)
    throw std::invalid_argument("similarity matrix size does not match its shape");
  for (float v : s.values) {
    if (!std::isfinite(v)) throw std::invalid_argument("similarity matrix has a non-finite value");
  }
}

}  // namespace

void validate(const LocalizeConfig& c) {
  if (!std::isfinite(c.gap) || c.gap < 0) throw std::invalid_argument("gap must be a finite number >= 0");
  if (!std::isfinite(c.contrast_offset)) throw std::invalid_argument("contrast_offset must be a finite number");
  if (c.cap && !(std::isfinite(*c.cap) && *c.cap > 0)) throw std::invalid_argument("cap must be a finite number > 0");
  if (!std::isfinite(c.threshold)) throw std::invalid_argument("threshold must be a finite number");
  if (c.max_alignments == 0) throw std::invalid_argument("max_alignments must be >= 1");
  if (c.candidates == 0) throw std::invalid_argument("candidates must be >= 1");
}

void score_row(const float* row, std::size_t cols, const LocalizeConfig& c, float* out) {
  if (!c.enhance) {
    for (std::size_t j = 0; j < cols; ++j) out[j] = row[j] - c.contrast_offset;
    return;
  }
  similarity::enhance_row(row, cols, c.contrast_window == 0 ? cols : c.contrast_window, out);
  for (std::size_t j = 0; j < cols; ++j) out[j] -= c.contrast_offset;
}

SimilarityMatrix score_matrix(const SimilarityMatrix& s, const LocalizeConfig& c) {
  check_matrix(s);
  validate(c);
  SimilarityMatrix out(s.rows, s.cols);
  for (std::size_t i = 0; i < s.rows; ++i) score_row(s.row(i).data(), s.cols, c, out.row(i).data());
  return out;
}

std::vector<FrameMatch> frames_from_alignments(const std::vector<align::LocalAlignment>& alignments,
                                               const SimilarityMatrix& scores, const LocalizeConfig& c) {
  struct Candidate {
    float score;
    std::size_t map;
    align::Direction direction;
    std::size_t rank;  // position of the alignment in `alignments` (the engine's best-first order)
  };
  std::vector<std::vector<Candidate>> per_frame(scores.rows);
  const auto window = static_cast<std::ptrdiff_t>(c.score_window);

  for (std::size_t rank = 0; rank < alignments.size(); ++rank) {
    const auto& a = alignments[rank];
    if (a.pairs.empty() || a.score < c.threshold) continue;
    const std::size_t n = a.pairs.size();
    // path[k]: the alignment's score from its first pair through pair k, gaps included, without the cap.
    std::vector<double> path(n);
    for (std::size_t k = 0; k < n; ++k) {
      const auto [i, j] = a.pairs[k];
      if (i >= scores.rows || j >= scores.cols) throw std::invalid_argument("alignment pair outside the matrix");
      double v = scores(i, j);
      if (k > 0) {
        const auto [pi, pj] = a.pairs[k - 1];
        const std::size_t query_gaps = i - pi - 1;
        const std::size_t map_gaps = (j > pj ? j - pj : pj - j) - 1;
        v += path[k - 1] - static_cast<double>(c.gap) * static_cast<double>(query_gaps + map_gaps);
      }
      path[k] = v;
    }
    std::size_t next = 0;  // first pair with query index >= q
    for (std::size_t q = a.a_begin; q < a.a_end; ++q) {
      while (next < n && a.pairs[next].first < q) ++next;
      // Map frame: the pair of q, or interpolated between the pairs around a gap.
      std::size_t map = 0;
      if (a.pairs[next].first == q) {
        map = a.pairs[next].second;
      } else {
        const auto [i0, j0] = a.pairs[next - 1];
        const auto [i1, j1] = a.pairs[next];
        const double t = static_cast<double>(q - i0) / static_cast<double>(i1 - i0);
        map = static_cast<std::size_t>(
            std::lround(static_cast<double>(j0) + t * (static_cast<double>(j1) - static_cast<double>(j0))));
      }
      // Local score: pairs with query index in [q - window, q + window].
      const auto lo_q = static_cast<std::ptrdiff_t>(q) - window;
      const auto hi_q = static_cast<std::ptrdiff_t>(q) + window;
      const auto lo = std::lower_bound(a.pairs.begin(), a.pairs.end(), lo_q, [](const auto& p, std::ptrdiff_t v) {
        return static_cast<std::ptrdiff_t>(p.first) < v;
      });
      const auto hi = std::upper_bound(a.pairs.begin(), a.pairs.end(), hi_q, [](std::ptrdiff_t v, const auto& p) {
        return v < static_cast<std::ptrdiff_t>(p.first);
      });
      double local = 0;
      if (lo < hi) {
        const auto first = static_cast<std::size_t>(lo - a.pairs.begin());
        const auto last = static_cast<std::size_t>(hi - a.pairs.begin()) - 1;
        local = path[last] - path[first] + scores(a.pairs[first].first, a.pairs[first].second);
      }
      per_frame[q].push_back({static_cast<float>(local), map, a.direction, rank});
    }
  }

  std::vector<FrameMatch> frames(scores.rows);
  for (std::size_t q = 0; q < scores.rows; ++q) {
    auto& cands = per_frame[q];
    if (cands.empty()) continue;
    std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
      if (x.score != y.score) return x.score > y.score;
      return x.rank < y.rank;
    });
    FrameMatch& f = frames[q];
    f.covered = true;
    f.map = cands.front().map;
    f.score = cands.front().score;
    f.direction = cands.front().direction;
    for (const auto& cand : cands) {
      if (f.candidates.size() >= c.candidates) break;
      if (std::find(f.candidates.begin(), f.candidates.end(), cand.map) == f.candidates.end())
        f.candidates.push_back(cand.map);
    }
  }
  return frames;
}

LocalizeResult localize_sequence(const SimilarityMatrix& s, const LocalizeConfig& c) {
  const SimilarityMatrix scores = score_matrix(s, c);
  align::AlignConfig ac;
  ac.gap_a = c.gap;
  ac.gap_b = c.gap;
  ac.cap = c.cap;
  ac.threshold = c.threshold;
  ac.max_alignments = c.max_alignments;
  const auto source = align::ScoreSource::dense(std::span<const float>(scores.values), scores.rows, scores.cols);
  LocalizeResult r;
  r.alignments = c.reverse ? align::local_alignments_both(source, ac, c.threads) : align::local_alignments(source, ac);
  r.frames = frames_from_alignments(r.alignments, scores, c);
  return r;
}

std::vector<FrameMatch> single_frame_matches(const SimilarityMatrix& s, std::size_t candidates) {
  check_matrix(s);
  if (candidates == 0) throw std::invalid_argument("candidates must be >= 1");
  std::vector<FrameMatch> frames(s.rows);
  std::vector<std::size_t> order(s.cols);
  const std::size_t k = std::min(candidates, s.cols);
  for (std::size_t q = 0; q < s.rows; ++q) {
    const auto row = s.row(q);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t x, std::size_t y) { return row[x] != row[y] ? row[x] > row[y] : x < y; });
    FrameMatch& f = frames[q];
    f.covered = true;
    f.map = order[0];
    f.score = row[order[0]];
    f.candidates.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k));
  }
  return frames;
}

}  // namespace seqtopo::localize
