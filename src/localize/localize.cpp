#include "seqtopo/localize/localize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "masked_scores.hpp"
#include "seqtopo/align/pair_posterior.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/significance/low_information.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::localize {

namespace {

void check_shape(const SimilarityMatrix& s) {
  if (s.empty()) throw std::invalid_argument("empty similarity matrix");
  if (s.values.size() != s.rows * s.cols)
    throw std::invalid_argument("similarity matrix size does not match its shape");
}

void check_matrix(const SimilarityMatrix& s) {
  check_shape(s);
  for (float v : s.values) {
    if (!std::isfinite(v)) throw std::invalid_argument("similarity matrix has a non-finite value");
  }
}

}  // namespace

void validate_speeds(std::span<const double> speeds) {
  if (speeds.empty() || speeds.front() != 1.0)
    throw std::invalid_argument("speeds must list 1 (the query as recorded) first, then any others");
  for (double v : speeds) {
    if (!(std::isfinite(v) && v >= 1.0 / kMaxSpeed && v <= kMaxSpeed))
      throw std::invalid_argument("speeds must be between 1/" + std::to_string(static_cast<int>(kMaxSpeed)) + " and " +
                                  std::to_string(static_cast<int>(kMaxSpeed)) + " map frames per query frame");
  }
}

void validate(const LocalizeConfig& c) {
  if (!std::isfinite(c.search.gap) || c.search.gap < 0) throw std::invalid_argument("gap must be a finite number >= 0");
  if (!std::isfinite(c.score.contrast_offset)) throw std::invalid_argument("contrast_offset must be a finite number");
  if (c.search.cap && !(std::isfinite(*c.search.cap) && *c.search.cap > 0))
    throw std::invalid_argument("cap must be a finite number > 0");
  if (!std::isfinite(c.significance.threshold)) throw std::invalid_argument("threshold must be a finite number");
  if (!(c.significance.max_e_value && std::isfinite(*c.significance.max_e_value) && *c.significance.max_e_value > 0))
    throw std::invalid_argument("significance.max_e_value must be set, finite and > 0");
  if (c.search.min_separation != 0) throw std::invalid_argument("search.min_separation must be 0 (no self pairs)");
  if (c.max_alignments == 0) throw std::invalid_argument("max_alignments must be >= 1");
  if (c.candidates == 0) throw std::invalid_argument("candidates must be >= 1");
  if (!(c.min_confidence >= 0 && c.min_confidence <= 1))
    throw std::invalid_argument("min_confidence must be in [0, 1]");
  if (c.lag > kMaxLag) throw std::invalid_argument("lag must be at most " + std::to_string(kMaxLag) + " frames");
  validate_speeds(c.speeds);
}

void score_row(const float* row, std::size_t cols, const LocalizeConfig& c, float* out) {
  if (!c.enhance) {
    for (std::size_t j = 0; j < cols; ++j) out[j] = row[j] - c.score.contrast_offset;
    return;
  }
  similarity::enhance_row(row, cols, c.score.contrast_window == 0 ? cols : c.score.contrast_window, out);
  for (std::size_t j = 0; j < cols; ++j) out[j] -= c.score.contrast_offset;
}

SimilarityMatrix score_matrix(const SimilarityMatrix& s, const LocalizeConfig& c) {
  check_matrix(s);
  validate(c);
  SimilarityMatrix out(s.rows, s.cols);
  for (std::size_t i = 0; i < s.rows; ++i) score_row(s.row(i).data(), s.cols, c, out.row(i).data());
  return out;
}

namespace {

// path[k]: the alignment's score from its first pair through pair k, gaps included, without the cap.
std::vector<double> path_prefix(const align::LocalAlignment& a, const SimilarityMatrix& scores, double gap) {
  std::vector<double> path(a.pairs.size());
  for (std::size_t k = 0; k < a.pairs.size(); ++k) {
    const auto [i, j] = a.pairs[k];
    if (i >= scores.rows || j >= scores.cols) throw std::invalid_argument("alignment pair outside the matrix");
    double v = scores(i, j);
    if (k > 0) {
      const auto [pi, pj] = a.pairs[k - 1];
      const std::size_t query_gaps = i - pi - 1;
      const std::size_t map_gaps = (j > pj ? j - pj : pj - j) - 1;
      v += path[k - 1] - gap * static_cast<double>(query_gaps + map_gaps);
    }
    path[k] = v;
  }
  return path;
}

// The alignment's own score gained over its pairs with query index in [q - window, q + window].
double local_score(const align::LocalAlignment& a, const std::vector<double>& path, const SimilarityMatrix& scores,
                   std::size_t q, std::size_t window) {
  const auto lo_q = static_cast<std::ptrdiff_t>(q) - static_cast<std::ptrdiff_t>(window);
  const auto hi_q = static_cast<std::ptrdiff_t>(q) + static_cast<std::ptrdiff_t>(window);
  const auto lo = std::lower_bound(a.pairs.begin(), a.pairs.end(), lo_q, [](const auto& p, std::ptrdiff_t v) {
    return static_cast<std::ptrdiff_t>(p.first) < v;
  });
  const auto hi = std::upper_bound(a.pairs.begin(), a.pairs.end(), hi_q, [](std::ptrdiff_t v, const auto& p) {
    return v < static_cast<std::ptrdiff_t>(p.first);
  });
  if (lo >= hi) return 0;
  const auto first = static_cast<std::size_t>(lo - a.pairs.begin());
  const auto last = static_cast<std::size_t>(hi - a.pairs.begin()) - 1;
  return path[last] - path[first] + scores(a.pairs[first].first, a.pairs[first].second);
}

// frames_from_alignments, alignments less likely real than `min_real` left out.
std::vector<FrameMatch> frames_of(const std::vector<align::LocalAlignment>& alignments,
                                  const std::vector<double>& e_values, double lambda, const SimilarityMatrix& scores,
                                  const LocalizeConfig& c, double min_real) {
  if (e_values.size() != alignments.size()) throw std::invalid_argument("one E-value per alignment expected");
  struct Candidate {
    double confidence;
    float score;
    std::size_t map;
    align::Direction direction;
    std::size_t rank;   // position of the alignment in `alignments` (the engine's best-first order)
    bool inside;        // the row is between the alignment's first and last pair
    double log_weight;  // ln(P(revisit | E) * exp(lambda * path score))
  };
  std::vector<std::vector<Candidate>> per_frame(scores.rows);
  align::PosteriorConfig pc;
  pc.lambda = lambda;
  pc.gap_a = pc.gap_b = c.search.gap;
  pc.band = c.posterior_band;
  pc.tolerance = c.tolerance;
  const auto source = align::ScoreSource::dense(std::span<const float>(scores.values), scores.rows, scores.cols);

  for (std::size_t rank = 0; rank < alignments.size(); ++rank) {
    const auto& a = alignments[rank];
    if (a.pairs.empty()) continue;
    const double e = e_values[rank];
    const double real = std::isfinite(e) ? significance::revisit_probability(e, *c.significance.max_e_value)
                                         : (a.score >= c.significance.threshold ? 1.0 : 0.0);
    if (real < min_real) continue;
    const std::vector<double> path = path_prefix(a, scores, c.search.gap);
    // Between the alignment's first and last pair the row is on it: where along it, given that (as the map's
    // pairs). Past its ends, whether a chain extending it reaches the row at all is part of the answer.
    align::PosteriorConfig wide = pc;
    wide.tolerance = pc.band;
    const std::vector<align::RowPosterior> rows = align::row_posteriors(a, source, pc);
    const std::vector<align::RowPosterior> covered = align::row_posteriors(a, source, wide);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const auto& r = rows[k];
      const bool inside = r.row >= a.pairs.front().first && r.row <= a.pairs.back().first;
      const double posterior = inside && k < covered.size() && covered[k].row == r.row && covered[k].posterior > 0
                                   ? std::min(1.0, r.posterior / covered[k].posterior)
                                   : r.posterior;
      per_frame[r.row].push_back({real * posterior,
                                  static_cast<float>(local_score(a, path, scores, r.row, c.score_window)), r.col,
                                  a.direction, rank, inside, std::log(real) + lambda * path.back()});
    }
  }

  std::vector<FrameMatch> frames(scores.rows);
  for (std::size_t q = 0; q < scores.rows; ++q) {
    auto& cands = per_frame[q];
    FrameMatch& f = frames[q];
    if (cands.empty()) {
      // No band reaches the frame: its best scored cell, with no confidence.
      const auto row = scores.row(q);
      f.map = static_cast<std::size_t>(std::max_element(row.begin(), row.end()) - row.begin());
      f.candidates = {f.map};
      continue;
    }
    // Split evidence: alignments that each run through the frame (it lies between their first and last pairs) at
    // places further apart than the tolerance are rival accounts of it (a look-alike stretch of the map driven
    // once), each as likely as its share of their weights P(revisit | E) exp(lambda * score) (their chains' shares
    // of the partition function, each alignment's summed as its best chain). One alignment through the frame, or
    // rivals of chance, leave the confidence as it was; an alignment that reaches the frame only past an end
    // (the route before or after a revisit) is no rival: several revisits follow one another along a query.
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& cand : cands) {
      if (cand.inside) top = std::max(top, cand.log_weight);
    }
    if (std::isfinite(top)) {
      std::vector<double> weight(cands.size(), 0.0);
      double total = 0;
      for (std::size_t k = 0; k < cands.size(); ++k) {
        if (cands[k].inside) total += weight[k] = std::exp(cands[k].log_weight - top);
      }
      for (auto& cand : cands) {
        if (!cand.inside) continue;
        double near = 0;
        for (std::size_t k = 0; k < cands.size(); ++k) {
          const std::size_t d = cands[k].map > cand.map ? cands[k].map - cand.map : cand.map - cands[k].map;
          if (d <= c.tolerance) near += weight[k];
        }
        cand.confidence *= std::min(1.0, near / total);
      }
    }
    std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
      if (x.confidence != y.confidence) return x.confidence > y.confidence;
      if (x.score != y.score) return x.score > y.score;
      return x.rank < y.rank;
    });
    const Candidate& best = cands.front();
    f.map = best.map;
    f.score = best.score;
    f.confidence = best.confidence;
    f.e_value = e_values[best.rank];
    f.alignment = best.rank;
    f.direction = best.direction;
    f.covered = f.confidence >= c.min_confidence;
    for (const auto& cand : cands) {
      if (f.candidates.size() >= c.candidates) break;
      if (std::find(f.candidates.begin(), f.candidates.end(), cand.map) == f.candidates.end())
        f.candidates.push_back(cand.map);
    }
  }
  return frames;
}

}  // namespace

std::vector<FrameMatch> frames_from_alignments(const std::vector<align::LocalAlignment>& alignments,
                                               const std::vector<double>& e_values, double lambda,
                                               const SimilarityMatrix& scores, const LocalizeConfig& c) {
  return frames_of(alignments, e_values, lambda, scores, c, 0.0);
}

namespace {

// Every positive alignment of the scores, best first (the real ones and the chance ones, the statistics' sample), and
// each one's evidence: its own path's score (a capped alignment's is its path).
std::vector<align::LocalAlignment> align_scores(const SimilarityMatrix& scores, const LocalizeConfig& c,
                                                std::vector<double>& path_scores) {
  check_matrix(scores);
  validate(c);
  align::AlignConfig ac;
  ac.gap_a = c.search.gap;
  ac.gap_b = c.search.gap;
  ac.cap = c.search.cap;
  ac.threshold = 0.0F;
  ac.max_alignments = c.max_alignments;
  const auto source = align::ScoreSource::dense(std::span<const float>(scores.values), scores.rows, scores.cols);
  std::vector<align::LocalAlignment> alignments =
      c.search.reverse ? align::local_alignments_both(source, ac, c.threads) : align::local_alignments(source, ac);
  path_scores.clear();
  for (const auto& a : alignments) {
    path_scores.push_back(c.search.cap ? align::path_score(a, source, c.search.gap, c.search.gap) : a.score);
  }
  return alignments;
}

}  // namespace

LocalizeResult search_scores(const SimilarityMatrix& scores, const LocalizeConfig& c) {
  LocalizeResult r;
  std::vector<double> path_scores;
  r.alignments = align_scores(scores, c, path_scores);
  // The fit on the declumped alignments, shadows left out.
  std::vector<double> best_first;
  for (std::size_t k = 0; k < r.alignments.size(); ++k) {
    if (!significance::shadows_earlier(r.alignments, k, significance::kShadowReach))
      best_first.push_back(r.alignments[k].score);
  }
  r.statistics = significance::fit_declumped_scores(
      best_first, significance::search_area(scores.rows, scores.cols, false, 0, c.search.reverse));
  for (double p : path_scores) r.e_values.push_back(r.statistics.valid() ? r.statistics.e_value(p) : std::nan(""));
  return r;
}

namespace {

// A frame not in the map by its own evidence (confidence below 1/2: only a chance alignment reaches it,
// past the end of a revisit whose last frames are weak or dark, or a map frame near its edge) has no answer it can
// be sure of. Its guess is the nearest frame in the map carried on along that frame's alignment, at its own (low)
// confidence still: the robot most likely went on along the route it was localized on (before, the weak
// alignment's cell, often a chance one elsewhere). Carried past an end of the map by at most `tolerance` frames, the
// end is the nearest map frame (and a guess the tolerance counts right); further, the robot has left the mapped
// route (or closed a loop): its own guess stands.
//
// Tried and left: a carried guess as probable as a two-state chain along it makes it (on the route or off it, each
// cell's evidence exp(lambda * score)). On the corridor split the weak last frames of a revisit are right, but a
// query that leaves the map's route at once scores the same in its first frames: ten frames somewhere new stayed
// "in the map" at 0.6-0.96. Only the frame's own evidence gives its confidence.
//
// A frame is carried on at the pace of its anchor's alignment: map frames per query frame from its first pair to its
// last (a query driven at 1.5 times the map's speed but aligned as it was recorded, with a gap every other frame,
// goes on at 1.5; a window of its pairs around the anchor drifted 3-7 frames over a long weak stretch), else
// `speed[anchor]`, the speed of the search that answered it (empty: 1).
void carry_on(LocalizeResult& r, std::size_t cols, std::size_t tolerance, const std::vector<double>& speed) {
  const auto pace = [&](std::size_t from) {
    const double searched = speed.empty() ? 1.0 : speed[from];
    const FrameMatch& k = r.frames[from];
    if (k.alignment >= r.alignments.size()) return searched;
    const auto& pairs = r.alignments[k.alignment].pairs;
    if (pairs.size() < 2 || pairs.back().first == pairs.front().first) return searched;
    const auto [i0, j0] = pairs.front();
    const auto [i1, j1] = pairs.back();
    const double frames = static_cast<double>(j1 > j0 ? j1 - j0 : j0 - j1);
    return std::clamp(frames / static_cast<double>(i1 - i0), 1.0 / kMaxSpeed, kMaxSpeed);
  };
  // More likely right than wrong, whatever min_confidence decides (the guesses do not move with it).
  const auto sure = [&](std::size_t q) { return r.frames[q].confidence >= 0.5; };
  const std::size_t n = r.frames.size();
  std::vector<std::size_t> before(n, FrameMatch::npos), after(n, FrameMatch::npos);
  for (std::size_t q = 0, last = FrameMatch::npos; q < n; ++q) before[q] = last = sure(q) ? q : last;
  for (std::size_t q = n, next = FrameMatch::npos; q-- > 0;) after[q] = next = sure(q) ? q : next;
  for (std::size_t q = 0; q < n; ++q) {
    if (sure(q)) continue;
    const std::size_t from = before[q] != FrameMatch::npos ? before[q] : after[q];
    if (from == FrameMatch::npos) return;  // nothing localized at all
    const FrameMatch& k = r.frames[from];
    const double frames = static_cast<double>(static_cast<long long>(q) - static_cast<long long>(from)) * pace(from);
    const long long step = std::llround(frames);
    const long long guess = static_cast<long long>(k.map) + (k.direction == align::Direction::forward ? step : -step);
    const auto past = static_cast<long long>(tolerance);
    if (guess < -past || guess >= static_cast<long long>(cols) + past) continue;
    FrameMatch& f = r.frames[q];
    f.map = static_cast<std::size_t>(std::clamp(guess, 0LL, static_cast<long long>(cols) - 1));
    // The carried guess first, then the frame's own candidates but it, as many as it had.
    const std::size_t kept = std::max<std::size_t>(f.candidates.size(), 1);
    std::erase(f.candidates, f.map);
    f.candidates.insert(f.candidates.begin(), f.map);
    f.candidates.resize(std::min(f.candidates.size(), kept));
  }
}

// The alignments and frames' own answers of one search (no carrying on): its E-values multiplied by `searches` (the
// speeds tried, each a search of its own), the alignments less likely real than `min_real` giving no answer.
LocalizeResult search_and_answer(const SimilarityMatrix& scores, const LocalizeConfig& c, double searches,
                                 double min_real) {
  LocalizeResult r = search_scores(scores, c);
  for (double& e : r.e_values) e *= searches;
  // Without a fit, lambda from the cells (an upper bound on the gapped one), else 1.
  double lambda = r.statistics.lambda;
  if (!r.statistics.valid()) {
    lambda = significance::ungapped_lambda(scores.values);
    if (!(lambda > 0)) lambda = 1.0;
  }
  r.frames = frames_of(r.alignments, r.e_values, lambda, scores, c, min_real);
  return r;
}

// The frames first + round(k * step), k = 0, 1, ..., below `end`.
std::vector<std::size_t> frames_at_step(std::size_t first, std::size_t end, double step) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0;; ++k) {
    const auto m = first + static_cast<std::size_t>(std::llround(static_cast<double>(k) * step));
    if (m >= end) break;
    out.push_back(m);
  }
  return out;
}

// The searches a speed makes: one per phase of the frames it skips (2 at 1.5 and 2: the even and the odd map frames
// for a query twice as fast, which may have been taken between the map's frames).
std::size_t phases(double speed) { return static_cast<std::size_t>(std::ceil(std::max(speed, 1.0 / speed) - 1e-9)); }

// The config on the map resampled at `speed`: its tolerance in map frames as columns.
LocalizeConfig at_speed(const LocalizeConfig& c, double speed) {
  LocalizeConfig at = c;
  at.tolerance = static_cast<std::size_t>(std::llround(static_cast<double>(c.tolerance) / speed));
  return at;
}

// A localization of a submatrix with its query frames and map frames put back: `row[i]` is row i's query frame,
// `frame[k]` column k's map frame (both increasing).
void to_query_and_map_frames(LocalizeResult& r, const std::vector<std::size_t>& row,
                             const std::vector<std::size_t>& frame) {
  const auto put_back = [](std::size_t& begin, std::size_t& end, const std::vector<std::size_t>& to) {
    if (end > begin) {
      begin = to[begin];
      end = to[end - 1] + 1;
    }
  };
  for (auto& a : r.alignments) {
    for (auto& p : a.pairs) p = {row[p.first], frame[p.second]};
    put_back(a.a_begin, a.a_end, row);
    put_back(a.b_begin, a.b_end, frame);
  }
  for (auto& f : r.frames) {
    f.map = frame[f.map];
    for (auto& m : f.candidates) m = frame[m];  // distinct columns stay distinct frames: `frame` increases
  }
}

// The stretches of frames [begin, end) the answers leave unsure (confidence below 1/2), each widened by `margin`
// frames either side (merged where they meet).
std::vector<std::pair<std::size_t, std::size_t>> unsure_stretches(const std::vector<FrameMatch>& frames,
                                                                  std::size_t margin) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  const std::size_t n = frames.size();
  for (std::size_t q = 0; q < n; ++q) {
    if (frames[q].confidence >= 0.5) continue;
    const std::size_t begin = q > margin ? q - margin : 0, end = std::min(n, q + margin + 1);
    if (!out.empty() && begin <= out.back().second) {
      out.back().second = std::max(out.back().second, end);
    } else {
      out.emplace_back(begin, end);
    }
  }
  return out;
}

// The query at `speed` against the map, where rows [begin, end) are: a faster query (speed > 1) against the map's
// frames phase + round(k * speed), a slower one against every map frame with its rows begin + phase +
// round(k / speed) only (a map frame repeated for a slower query makes chance alignments of look-alike neighbours;
// the rows between lie on the alignment between them). Its E-values come from `statistics` (the first speed's fit: the
// same cells, the same chance tail) over the whole search at this speed, times `searches`; only alignments more likely
// a revisit than not answer (a chance one cannot win a frame; their posteriors were most of the cost). Returns the
// answers (one per row of `rows`, in query rows and map frames) and the alignments.
LocalizeResult search_stretch(const SimilarityMatrix& scores, std::size_t begin, std::size_t end, double speed,
                              std::size_t phase, const LocalizeConfig& c,
                              const significance::ScoreStatistics& statistics, double searches,
                              std::vector<std::size_t>& rows) {
  const std::vector<std::size_t> frame = frames_at_step(speed >= 1 ? phase : 0, scores.cols, std::max(1.0, speed));
  rows = frames_at_step(begin + (speed < 1 ? phase : 0), end, 1 / std::min(1.0, speed));
  if (frame.size() < 2 || rows.size() < 2) return {};
  SimilarityMatrix sub(rows.size(), frame.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < frame.size(); ++k) sub(i, k) = scores(rows[i], frame[k]);
  }
  const LocalizeConfig at = at_speed(c, std::max(1.0, speed));
  LocalizeResult r;
  std::vector<double> path_scores;
  r.alignments = align_scores(sub, at, path_scores);
  significance::ScoreStatistics whole = statistics;
  whole.area = significance::search_area(
      static_cast<std::size_t>(std::llround(static_cast<double>(scores.rows) * std::min(1.0, speed))), frame.size(),
      false, 0, c.search.reverse);
  for (double p : path_scores) r.e_values.push_back(searches * whole.e_value(p));
  r.frames = frames_of(r.alignments, r.e_values, statistics.lambda, sub, at, 0.5);
  to_query_and_map_frames(r, rows, frame);
  if (speed < 1) {
    // The rows a slower query's search skipped lie on its alignment between the rows either side of them, when
    // one alignment answered both: at the map frame between theirs, as sure as the less sure of the two.
    std::vector<FrameMatch> all(end - begin);
    for (std::size_t i = 0; i < rows.size(); ++i) all[rows[i] - begin] = std::move(r.frames[i]);
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
      const FrameMatch &x = all[rows[i] - begin], &y = all[rows[i + 1] - begin];
      if (x.alignment == FrameMatch::npos || x.alignment != y.alignment) continue;
      for (std::size_t q = rows[i] + 1; q < rows[i + 1]; ++q) {
        const double t = static_cast<double>(q - rows[i]) / static_cast<double>(rows[i + 1] - rows[i]);
        FrameMatch& f = all[q - begin];
        f = x.confidence <= y.confidence ? x : y;
        f.map = static_cast<std::size_t>(
            std::llround(static_cast<double>(x.map) + t * (static_cast<double>(y.map) - static_cast<double>(x.map))));
        f.candidates = {f.map};
      }
    }
    r.frames = std::move(all);
    rows.resize(end - begin);
    std::iota(rows.begin(), rows.end(), begin);
  }
  return r;
}

}  // namespace

LocalizeResult localize_scores(const SimilarityMatrix& scores, const LocalizeConfig& c) {
  validate_speeds(c.speeds);
  double searches = 0;
  for (const double v : c.speeds) searches += static_cast<double>(phases(v));
  LocalizeResult best = search_and_answer(scores, c, searches, 0.0);  // speeds[0] is 1 (validate_speeds)
  std::vector<double> speed(best.frames.size(), 1.0);                 // of the search that answered each frame
  // The other speeds where the first leaves frames unsure, with its statistics (none: no other speed).
  const std::vector<std::pair<std::size_t, std::size_t>> stretches =
      best.statistics.valid() ? unsure_stretches(best.frames, c.posterior_band) : decltype(stretches){};
  std::vector<std::size_t> rows;
  for (std::size_t s = 1; s < c.speeds.size(); ++s) {
    const double v = c.speeds[s];
    for (std::size_t phase = 0; phase < phases(v); ++phase) {
      for (const auto& [begin, end] : stretches) {
        LocalizeResult r = search_stretch(scores, begin, end, v, phase, c, best.statistics, searches, rows);
        if (r.alignments.empty()) continue;
        // An unsure frame takes the most confident answer of the other speeds (the first listed on a tie); every
        // speed's alignments are kept, each answer pointing at its own.
        const std::size_t offset = best.alignments.size();
        for (std::size_t i = 0; i < rows.size(); ++i) {
          const std::size_t q = rows[i];
          FrameMatch& f = r.frames[i];
          if (speed[q] == 1.0 && best.frames[q].confidence >= 0.5) continue;
          if (!(f.confidence > best.frames[q].confidence)) continue;
          if (f.alignment != FrameMatch::npos) f.alignment += offset;
          best.frames[q] = std::move(f);
          speed[q] = v;
        }
        best.alignments.insert(best.alignments.end(), std::make_move_iterator(r.alignments.begin()),
                               std::make_move_iterator(r.alignments.end()));
        best.e_values.insert(best.e_values.end(), r.e_values.begin(), r.e_values.end());
      }
    }
  }
  carry_on(best, scores.cols, c.tolerance, speed);
  return best;
}

LocalizeResult localize_sequence(const SimilarityMatrix& s, const LocalizeConfig& c) {
  return localize_scores(score_matrix(s, c), c);
}

namespace {

// The fusion of one row from each descriptor's row as the alignment reads it (enhanced, or the similarity itself
// without enhancement), `enhanced(d)` giving descriptor d's: the weighted average, then the offset.
template <class Row>
void fuse_row(std::size_t descriptors, std::size_t cols, float offset, std::span<const double> weights, float* out,
              Row&& enhanced) {
  if (!weights.empty() && weights.size() != descriptors) throw std::invalid_argument("one weight per descriptor");
  double total = 0;
  for (std::size_t d = 0; d < descriptors; ++d) total += weights.empty() ? 1.0 : weights[d];
  if (!(total > 0)) throw std::invalid_argument("the descriptors' weights sum to 0");
  std::fill(out, out + cols, 0.0F);
  for (std::size_t d = 0; d < descriptors; ++d) {
    if (!weights.empty() && weights[d] == 0) continue;
    const float* row = enhanced(d);
    if (weights.empty()) {
      for (std::size_t j = 0; j < cols; ++j) out[j] += row[j];
    } else {
      const auto w = static_cast<float>(weights[d] / total);
      for (std::size_t j = 0; j < cols; ++j) out[j] += w * row[j];
    }
  }
  // Equal weights: the sum divided by the count, as the map's fusion (mapping::enhanced_scores).
  const float count = weights.empty() ? static_cast<float>(descriptors) : 1.0F;
  for (std::size_t j = 0; j < cols; ++j) out[j] = out[j] / count - offset;
}

}  // namespace

void fused_score_row(std::span<const float* const> rows, std::size_t cols, const LocalizeConfig& c, float* out,
                     float* scratch, std::span<const double> weights) {
  if (rows.empty()) throw std::invalid_argument("no similarity row");
  if (rows.size() == 1) {
    if (!weights.empty() && weights.size() != 1) throw std::invalid_argument("one weight per descriptor");
    score_row(rows.front(), cols, c, out);
    return;
  }
  fuse_row(rows.size(), cols, c.score.contrast_offset, weights, out, [&](std::size_t d) {
    if (!c.enhance) return rows[d];
    similarity::enhance_row(rows[d], cols, c.score.contrast_window == 0 ? cols : c.score.contrast_window, scratch);
    return static_cast<const float*>(scratch);
  });
}

namespace {

// The shapes only: the values are checked where each matrix is first read (score_matrix), once.
void check_same_shape(std::span<const SimilarityMatrix> ss) {
  if (ss.empty()) throw std::invalid_argument("no similarity matrix");
  for (const auto& s : ss) {
    check_shape(s);
    if (s.rows != ss.front().rows || s.cols != ss.front().cols) {
      throw std::invalid_argument("the similarity matrices of the descriptors differ in shape (" +
                                  std::to_string(s.rows) + " x " + std::to_string(s.cols) + " and " +
                                  std::to_string(ss.front().rows) + " x " + std::to_string(ss.front().cols) + ")");
    }
  }
}

// Each similarity as the alignment reads it before the offset: its rows contrast-enhanced (the similarity itself
// without enhancement). Made once for the weights and the fusion (each enhancement is a pass over the table).
std::vector<SimilarityMatrix> enhanced_each(std::span<const SimilarityMatrix> ss, const LocalizeConfig& c) {
  LocalizeConfig unshifted = c;
  unshifted.score.contrast_offset = 0;
  std::vector<SimilarityMatrix> out;
  out.reserve(ss.size());
  for (const auto& s : ss) out.push_back(score_matrix(s, unshifted));
  return out;
}

// score_matrix from its enhanced table: the same values (x - 0 - offset is x - offset).
SimilarityMatrix minus(const SimilarityMatrix& enhanced, float offset) {
  SimilarityMatrix out = enhanced;
  for (auto& v : out.values) v -= offset;
  return out;
}

// fused_score_matrix from the enhanced tables.
SimilarityMatrix fuse_enhanced(const std::vector<SimilarityMatrix>& enhanced, std::span<const double> weights,
                               float offset) {
  const std::size_t rows = enhanced.front().rows, cols = enhanced.front().cols;
  SimilarityMatrix out(rows, cols);
  for (std::size_t i = 0; i < rows; ++i) {
    fuse_row(enhanced.size(), cols, offset, weights, out.row(i).data(),
             [&](std::size_t d) { return enhanced[d].row(i).data(); });
  }
  return out;
}

// descriptor_weights from the enhanced tables (see the header).
std::vector<double> weights_of_enhanced(const std::vector<SimilarityMatrix>& enhanced, const LocalizeConfig& c) {
  const std::size_t descriptors = enhanced.size();
  std::vector<double> equal(descriptors, 1.0);
  if (descriptors < 2 || !c.enhance) return equal;
  const float offset = c.score.contrast_offset;
  const double strict = *c.significance.max_e_value / static_cast<double>(descriptors);
  std::vector<bool> sees_alone(descriptors, false);
  std::vector<std::pair<std::size_t, std::size_t>> seen;  // the pairs of the alignments found at `strict`
  for (std::size_t d = 0; d < descriptors; ++d) {
    // Its alignments and their E-values: the frames' answers (posteriors) are not needed here.
    const LocalizeResult alone = search_scores(minus(enhanced[d], offset), c);
    if (!alone.statistics.valid()) continue;
    for (std::size_t k = 0; k < alone.alignments.size(); ++k) {
      sees_alone[d] = sees_alone[d] || alone.e_values[k] <= *c.significance.max_e_value;
      if (alone.e_values[k] <= strict) {
        seen.insert(seen.end(), alone.alignments[k].pairs.begin(), alone.alignments[k].pairs.end());
      }
    }
  }
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  if (seen.size() < 2) return equal;
  std::vector<double> weights(descriptors, 0.0);
  for (std::size_t d = 0; d < descriptors; ++d) {
    // The aligned scores, enhanced minus the offset, read where they are.
    const SimilarityMatrix& e = enhanced[d];
    double chance = 0;
    for (float v : e.values) chance += v - offset;
    chance /= static_cast<double>(e.values.size());
    double sum = 0, sum2 = 0;
    for (const auto& [i, j] : seen) {
      const float v = e(i, j) - offset;
      sum += v, sum2 += static_cast<double>(v) * v;
    }
    const auto m = static_cast<double>(seen.size());
    const double mean = sum / m, sd = std::sqrt(std::max(0.0, sum2 / m - mean * mean));
    const bool blind = !sees_alone[d] && mean - chance < 3 * sd / std::sqrt(m);
    weights[d] = blind ? 0.0 : std::max(mean - chance, 0.0);
  }
  if (std::all_of(weights.begin(), weights.end(), [](double w) { return w == 0; })) return equal;
  return weights;
}

}  // namespace

SimilarityMatrix fused_score_matrix(std::span<const SimilarityMatrix> ss, const LocalizeConfig& c,
                                    std::span<const double> weights) {
  check_same_shape(ss);
  validate(c);
  if (ss.size() == 1) return score_matrix(ss.front(), c);
  return fuse_enhanced(enhanced_each(ss, c), weights, c.score.contrast_offset);
}

std::vector<double> descriptor_weights(std::span<const SimilarityMatrix> ss, const LocalizeConfig& c) {
  check_same_shape(ss);
  if (ss.size() < 2 || !c.enhance) {
    for (const auto& s : ss) check_matrix(s);
    return std::vector<double>(ss.size(), 1.0);
  }
  return weights_of_enhanced(enhanced_each(ss, c), c);
}

LocalizeResult localize_sequence(std::span<const SimilarityMatrix> ss, const LocalizeConfig& c) {
  return localize_sequence(ss, c, LowInformationFrames{});
}

void soft_mask(SimilarityMatrix& scores, const LowInformationFrames& frames) {
  if (frames.query.empty() && frames.map.empty()) return;
  const std::vector<bool> query = significance::frame_flags(frames.query, scores.rows, "low-information query frame");
  const std::vector<bool> map = frames.map.empty()
                                    ? std::vector<bool>{}
                                    : significance::frame_flags(frames.map, scores.cols, "low-information map frame");
  for (std::size_t q = 0; q < scores.rows; ++q) detail::soft_mask_row(scores.row(q).data(), scores.cols, query[q], map);
}

namespace {

// The alignments over soft-masked scores (soft_mask).
LocalizeResult localize_masked(SimilarityMatrix scores, const LocalizeConfig& c,
                               const LowInformationFrames& low_information) {
  soft_mask(scores, low_information);
  return localize_scores(scores, c);
}

}  // namespace

LocalizeResult localize_sequence(std::span<const SimilarityMatrix> ss, const LocalizeConfig& c,
                                 const LowInformationFrames& low_information) {
  check_same_shape(ss);
  if (ss.size() == 1) return localize_masked(score_matrix(ss.front(), c), c, low_information);
  const std::vector<SimilarityMatrix> enhanced = enhanced_each(ss, c);
  const std::vector<double> weights = weights_of_enhanced(enhanced, c);
  SimilarityMatrix fused = fuse_enhanced(enhanced, weights, 0.0F);
  LocalizeResult r = localize_masked(minus(fused, c.score.contrast_offset), c, low_information);
  r.fused_enhanced = std::move(fused);
  r.descriptor_weights = weights;
  for (std::size_t d = 0; d < weights.size(); ++d) {
    if (weights[d] == 0) r.blind_descriptors.push_back(d);
  }
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
