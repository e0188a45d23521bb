#include "seqtopo/mapping/map_builder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

#include "masked_frames.hpp"
#include "median.hpp"
#include "seqtopo/align/band_realignment.hpp"
#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/align/pair_posterior.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/stopwatch.hpp"
#include "seqtopo/mapping/graph_cleanup.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/significance/alignment_ends.hpp"
#include "seqtopo/significance/alignment_phase.hpp"
#include "seqtopo/significance/low_information.hpp"
#include "seqtopo/significance/tandem_repeats.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"
#include "seqtopo/similarity/hubness.hpp"

namespace seqtopo::mapping {
namespace {

using detail::median;

// `source` minus a constant, read a row segment at a time.
align::ScoreSource minus(const align::ScoreSource& source, float offset) {
  if (offset == 0.0F) return source;
  return source.derived(
      [source, offset](std::size_t i, std::size_t b, std::size_t e, align::Score* out) {
        source.read_row(i, b, e, out);
        for (std::size_t k = 0; k < e - b; ++k) out[k] -= offset;
      },
      [source, offset](std::size_t i, std::size_t j) { return source.at(i, j) - offset; });
}

using align::places_in_frames;

}  // namespace

MapConfig settings_in_frames(const MapConfig& c, double frames_per_place) {
  MapConfig f = c;
  f.score = align::in_frames(c.score, c.unit, frames_per_place);
  f.search = align::in_frames(c.search, c.unit, frames_per_place);
  if (c.unit == align::Unit::places)
    f.graph.topology.u_turn_separation =
        places_in_frames(static_cast<double>(c.graph.topology.u_turn_separation), frames_per_place);
  return f;
}

namespace {

std::vector<align::LocalAlignment> run_engine(const align::ScoreSource& scores, const align::AlignConfig& engine,
                                              MapConfig::Engine kind, bool reverse, unsigned threads) {
  if (kind == MapConfig::Engine::fast) {
    const align::FastOptions options{.threads = threads};
    return reverse ? align::fast_local_alignments_both(scores, engine, options)
                   : align::fast_local_alignments(scores, engine, options);
  }
  return reverse ? align::local_alignments_both(scores, engine, threads) : align::local_alignments(scores, engine);
}

// Chance alignments in the logarithmic phase stay short: their length grows like the log of the search area,
// in the linear phase like the sequence. The fitted (chance) alignments' median length in places against
// the log of the area in places: a generous bound that the logarithmic phase keeps even near the transition
// (measured in docs/significance.md).
bool logarithmic_phase(double chance_length_places, double area_places) {
  return chance_length_places <= std::max(4.0, std::log(std::max(area_places, 1.0)));
}

struct FitRun {
  significance::ScoreStatistics statistics;
  std::vector<align::LocalAlignment> alignments;
  std::vector<double> path_scores;
  std::size_t fitted = 0;    // alignments the fit could use (not shadows)
  double chance_length = 0;  // [places]
  double cell_mean = 0;      // of the cells the run read, off the self band
  // of a table drawn from them (significance/alignment_phase.hpp); none drawn: no sign of the linear phase
  double global_rate = -std::numeric_limits<double>::infinity();
};

// The fit's two checks of the logarithmic phase: its chance alignments stay short (against the search area in
// places), and the scores' global alignment rate is at most config.max_global_rate. Statistics are trusted only
// when they are valid and both hold: build_map's and the online early fit's (fit_table_statistics) rule alike.
struct PhaseChecks {
  bool short_chance = false;
  bool logarithmic = false;
};
PhaseChecks phase_checks(const FitRun& fit, const MapConfig& c, double area_places) {
  PhaseChecks p;
  p.short_chance = logarithmic_phase(fit.chance_length, area_places);
  const bool falling = !c.phase.max_global_rate || fit.global_rate <= *c.phase.max_global_rate;
  p.logarithmic = fit.statistics.valid() && p.short_chance && falling;
  return p;
}

// The statistics' run: the best `fit_alignments` declumped alignments of `scores` (any score > 0), with the
// fast engine and a cap far above chance; the fit uses those that are not shadows of earlier ones.
// Sequences longer than twice kFitBlock frames are fitted on kFitBlocks diagonal blocks of kFitBlock frames
// spread evenly along them, read once into memory: the statistics of a cell do not depend on the sequence's
// length (the area scales them), and the fit then costs the same for 10^4 frames streamed as for 4,000.
constexpr std::size_t kFitBlock = 2000, kFitBlocks = 4;
// The global alignment rate is taken on a 256 x 256 table drawn from about 65,536 of the fit's cells.
using significance::kPhaseCells;
using significance::kPhaseTable;

// The statistics' run's alignments, best first, in the full sequence's indices; `area` the cells searched.
std::vector<align::LocalAlignment> fit_alignments(const align::ScoreSource& scores, align::AlignConfig engine,
                                                  const MapConfig& c, double& area, double& cell_mean,
                                                  std::vector<float>& cell_sample) {
  const std::size_t n = scores.rows();
  const bool whole = n <= 2 * kFitBlock;
  // A sequence this short is fitted whole: where it is when it is in memory, else from a copy (a streamed source
  // recomputes its tiles for every alignment's traceback and declumping).
  const bool in_place = whole && scores.in_memory();
  const std::size_t size = whole ? n : kFitBlock, blocks = whole ? 1 : kFitBlocks;
  area = static_cast<double>(blocks) *
         significance::search_area(size, size, true, c.search.min_separation, c.search.reverse);
  if (!whole) engine.max_alignments = (engine.max_alignments + blocks - 1) / blocks;
  std::vector<align::LocalAlignment> all;
  std::vector<align::Score> block(in_place ? size : size * size);  // in place: one row at a time
  const double block_cells = significance::search_area(size, size, true, c.search.min_separation, false);
  const auto phase_stride =
      std::max<std::size_t>(1, static_cast<std::size_t>(static_cast<double>(blocks) * block_cells / kPhaseCells));
  double sum = 0;  // of the cells off the self band, for their mean
  std::size_t cells = 0;
  std::size_t to_sample = 0;  // cells until the next sampled one: cells % phase_stride == 0, without a division
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t start = blocks == 1 ? 0 : (n - size) * b / (blocks - 1);
    if (!in_place) {
      for (std::size_t i = 0; i < size; ++i) scores.read_row(start + i, start, start + size, block.data() + i * size);
    }
    for (std::size_t i = c.search.min_separation; i < size; ++i) {
      const align::Score* row = block.data() + (in_place ? 0 : i * size);
      if (in_place) scores.read_row(i, 0, i + 1 - c.search.min_separation, block.data());
      for (std::size_t j = 0; j + c.search.min_separation <= i; ++j) {
        sum += row[j];
        // Every stride-th cell, about kPhaseCells of the blocks' (the same cells whatever the thread count).
        if (to_sample-- == 0) {
          cell_sample.push_back(row[j]);
          to_sample = phase_stride - 1;
        }
        ++cells;
      }
    }
    auto found = run_engine(in_place ? scores : align::ScoreSource::dense(block, size, size), engine,
                            MapConfig::Engine::fast, c.search.reverse, c.threads);
    for (auto& a : found) {
      a.a_begin += start;
      a.a_end += start;
      a.b_begin += start;
      a.b_end += start;
      for (auto& [i, j] : a.pairs) i += start, j += start;
      all.push_back(std::move(a));
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.score > y.score; });
  cell_mean = cells > 0 ? sum / static_cast<double>(cells) : 0.0;
  return all;
}

// The source, telling `progress` the cells its readers have read of the `total` the passes search, at most the total
// less one (a traceback re-reads a few; the caller tells the total when the alignment ends), in steps of a
// thousandth.
align::ScoreSource told_progress(align::ScoreSource source, std::size_t total,
                                 const std::function<void(std::size_t, std::size_t)>& progress) {
  if (!progress || total < 2) return source;
  const std::size_t step = std::max<std::size_t>(1, total / 1000);
  auto cells = std::make_shared<std::atomic<std::size_t>>(0);
  auto told = std::make_shared<std::atomic<std::size_t>>(0);
  auto read = [source, cells, told, total, step, progress](std::size_t i, std::size_t j_begin, std::size_t j_end,
                                                           align::Score* out) {
    source.read_row(i, j_begin, j_end, out);
    const std::size_t done = std::min(total - 1, cells->fetch_add(j_end - j_begin) + (j_end - j_begin));
    std::size_t before = told->load(std::memory_order_relaxed);
    while (done >= before + step && !told->compare_exchange_weak(before, done)) {
    }
    if (done >= before + step) progress(done, total);
  };
  align::ScoreSource::CellReader cell = source.cell_reader();
  return source.derived(std::move(read), std::move(cell));
}

// A source computed when read (streamed scores), whose single cells are read more than once: the path scores, the
// end trimming and the bands' realignment each read every pair of every alignment, and a streamed cell costs its
// two windows of cosines. Each cell is computed once (up to a bound on the cells held); rows are read as they are.
align::ScoreSource remembering_cells(const align::ScoreSource& source) {
  if (source.in_memory()) return source;
  struct Memo {
    std::mutex mutex;
    std::unordered_map<std::uint64_t, align::Score> cells;
  };
  constexpr std::size_t kMaxCells = std::size_t{1} << 22;  // about 100 MB of map nodes at most
  auto memo = std::make_shared<Memo>();
  const std::uint64_t cols = source.cols();
  auto cell = [source, memo, cols](std::size_t i, std::size_t j) {
    const std::uint64_t key = i * cols + j;
    {
      const std::lock_guard lock(memo->mutex);
      if (const auto it = memo->cells.find(key); it != memo->cells.end()) return it->second;
    }
    const align::Score v = source.at(i, j);
    const std::lock_guard lock(memo->mutex);
    if (memo->cells.size() >= kMaxCells) memo->cells.clear();
    memo->cells.emplace(key, v);
    return v;
  };
  return source.derived(
      [source](std::size_t i, std::size_t b, std::size_t e, align::Score* out) { source.read_row(i, b, e, out); },
      std::move(cell));
}

FitRun fit_statistics(const align::ScoreSource& scores, const MapConfig& c, double frames_per_place,
                      std::size_t alignments) {
  align::AlignConfig engine = align_config(c);
  engine.threshold = 0.0F;
  engine.cap = 256.0F;  // far above any chance alignment in the logarithmic phase; int16 steps of 1/128
  engine.max_alignments = alignments;
  FitRun run;
  double area = 0;
  std::vector<float> cells;
  run.alignments = fit_alignments(scores, engine, c, area, run.cell_mean, cells);
  if (!cells.empty()) run.global_rate = significance::resampled_global_rate(cells, kPhaseTable, c.search.gap);
  std::vector<double> best_first;
  std::vector<std::size_t> fitted;  // indices of the alignments in best_first
  for (std::size_t k = 0; k < run.alignments.size(); ++k) {
    // Chance alignments stay far below the run's cap, where the engine's score is the path's; a path is scored
    // again only when the cap may have clipped it.
    const auto& a = run.alignments[k];
    run.path_scores.push_back(a.score < 0.5F * *engine.cap ? a.score
                                                           : align::path_score(a, scores, c.search.gap, c.search.gap));
    if (significance::shadows_earlier(run.alignments, k, significance::kShadowReach)) continue;
    best_first.push_back(run.alignments[k].score);
    fitted.push_back(k);
  }
  run.fitted = best_first.size();
  run.statistics = significance::fit_declumped_scores(best_first, area);
  if (run.statistics.valid()) {
    std::vector<double> lengths;
    for (std::size_t r = run.statistics.first_fitted_rank - 1; r < fitted.size(); ++r) {
      lengths.push_back(static_cast<double>(run.alignments[fitted[r]].pairs.size()) / frames_per_place);
    }
    run.chance_length = median(std::move(lengths));
  }
  return run;
}

// A sequence full of revisits and their shadows may leave too few chance alignments among the first
// fit_alignments: look further, up to 16 times as far.
FitRun fit_looking_further(const align::ScoreSource& scores, const MapConfig& c, double frames_per_place) {
  FitRun fit;
  for (std::size_t m = c.fit_alignments;; m *= 4) {
    fit = fit_statistics(scores, c, frames_per_place, m);
    if (fit.statistics.valid() || fit.alignments.size() < m || m >= 16 * c.fit_alignments) break;
  }
  return fit;
}

// A capped path's diagonals are the tie-breaking's, not the evidence's: each capped alignment is re-aligned
// without the cap in a band around it (align/band_realignment.hpp), over the rows it covers once its chance ends
// are trimmed (re-aligning first can reach the last row through a gap that the trim then counts against the
// tail). Paths moved onto one revisit's cells are that revisit found more than once: an alignment all of whose
// pairs are pairs of better ones (higher path scores) is left out; one that adds pairs stays, for the pruning to
// weigh. Returns the indices of the alignments kept, in order.
std::vector<std::size_t> realign_in_bands(std::vector<align::LocalAlignment>& alignments,
                                          const align::ScoreSource& scores, const align::AlignConfig& engine,
                                          double gap, std::size_t reach) {
  std::vector<std::size_t> order(alignments.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  bool moved = false;
  for (auto& a : alignments) {
    if (a.score < *engine.cap) continue;
    align::LocalAlignment best = align::realign_in_band(a, scores, engine, reach);
    moved = moved || best.pairs != a.pairs;
    a = std::move(best);
  }
  if (!moved) return order;
  std::vector<double> path(alignments.size());
  for (std::size_t k = 0; k < alignments.size(); ++k) path[k] = align::path_score(alignments[k], scores, gap, gap);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return path[x] > path[y]; });
  std::set<std::tuple<align::Direction, std::size_t, std::size_t>> taken;
  std::vector<std::size_t> kept;
  for (const std::size_t k : order) {
    const auto& a = alignments[k];
    const auto shared = std::count_if(a.pairs.begin(), a.pairs.end(), [&](const auto& p) {
      return taken.contains({a.direction, p.first, p.second});
    });
    if (static_cast<std::size_t>(shared) == a.pairs.size()) continue;
    kept.push_back(k);
    for (const auto& [i, j] : a.pairs) taken.insert({a.direction, i, j});
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

// MapConfig::odometry.evidence: the share of the statistics' run's chance alignments (E > 1) that the odometry
// gate passes, (passed + 1) / (tested + 2); 1 with fewer than 20 of them.
double chance_agreement(const FitRun& fit, std::span<const Pose2> odometry, const OdometryGate& gate) {
  std::vector<align::LocalAlignment> chance;
  for (std::size_t k = 0; k < fit.alignments.size(); ++k) {
    if (fit.statistics.e_value(fit.path_scores[k]) > 1.0) chance.push_back(fit.alignments[k]);
  }
  if (chance.size() < 20) return 1.0;
  const std::vector<bool> agree = consistent_with_odometry(chance, odometry, gate);
  const auto passed = static_cast<double>(std::count(agree.begin(), agree.end(), true));
  return (passed + 1.0) / (static_cast<double>(chance.size()) + 2.0);
}

}  // namespace

namespace {

// Throws std::invalid_argument unless the similarities are square and of one size.
void check_similarities(const std::vector<SimilarityMatrix>& similarities) {
  if (similarities.empty() || similarities.front().empty()) throw std::invalid_argument("empty similarity matrix");
  const std::size_t n = similarities.front().rows;
  for (const auto& s : similarities) {
    if (!s.square() || s.rows != n) {
      throw std::invalid_argument("similarity matrix must be square and " + std::to_string(n) + " x " +
                                  std::to_string(n) + ", got " + std::to_string(s.rows) + " x " +
                                  std::to_string(s.cols) +
                                  " (descriptors, one row per image, need seqtopo.similarity first)");
    }
  }
}

// The fusion of `count` enhanced matrices, next(d) giving the d-th: one is itself; several their mean, summed in
// the first one's storage as a sum started at zero would be, ((0 + e_0) + e_1 + ...) / count, so that no N x N sum
// is allocated beside them. `told` (when set) after each, with how many are done of how many.
SimilarityMatrix fused(std::size_t count, const std::function<SimilarityMatrix(std::size_t)>& next,
                       const std::function<void(std::size_t, std::size_t)>& told) {
  if (told) told(0, count);
  SimilarityMatrix sum = next(0);
  if (count == 1) {
    if (told) told(1, 1);
    return sum;
  }
  for (auto& v : sum.values) v = 0.0F + v;
  if (told) told(1, count);
  for (std::size_t d = 1; d < count; ++d) {
    const SimilarityMatrix e = next(d);
    for (std::size_t k = 0; k < sum.values.size(); ++k) sum.values[k] += e.values[k];
    if (told) told(d + 1, count);
  }
  const auto n = static_cast<float>(count);
  for (auto& v : sum.values) v = v / n;
  return sum;
}

// One similarity contrast-enhanced (itself when the window is 0), before the offset.
SimilarityMatrix enhanced_one(const SimilarityMatrix& s, std::size_t contrast_window) {
  return contrast_window == 0 ? s : similarity::enhance_contrast_symmetric(s, contrast_window, 0.0F);
}

}  // namespace

SimilarityMatrix enhanced_scores(const std::vector<SimilarityMatrix>& similarities, std::size_t contrast_window,
                                 const std::function<void(std::size_t, std::size_t)>& told) {
  check_similarities(similarities);
  return fused(
      similarities.size(), [&](std::size_t d) { return enhanced_one(similarities[d], contrast_window); }, told);
}

SimilarityMatrix alignment_scores(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config) {
  SimilarityMatrix s = enhanced_scores(similarities, config.score.contrast_window);
  if (config.score.contrast_window == 0) return s;
  for (auto& v : s.values) v -= config.score.contrast_offset;
  return s;
}

align::AlignConfig align_config(const MapConfig& config) {
  align::AlignConfig c;
  c.gap_a = c.gap_b = config.search.gap;
  c.cap = config.search.cap;
  c.threshold = config.significance.threshold;
  c.self = true;
  c.min_separation = config.search.min_separation;
  return c;
}

PlaceScale frames_per_place(const std::vector<SimilarityMatrix>& similarities) {
  double sum = 0;
  std::size_t found = 0;
  for (const auto& s : similarities) {
    const PlaceScale e = estimate_frames_per_place(align::ScoreSource::dense(s.values, s.rows, s.cols));
    if (e.found) {
      sum += e.frames_per_place;
      ++found;
    }
  }
  if (found == 0) return {};
  return {sum / static_cast<double>(found), true};
}

namespace {

// The aligned pairs of all `alignments`.
std::size_t pair_count(const std::vector<align::LocalAlignment>& alignments) {
  std::size_t n = 0;
  for (const auto& a : alignments) n += a.pairs.size();
  return n;
}

// Keeps alignments `which` (in that order) with their path scores and E-values.
void select_alignments(MapResult& result, const std::vector<std::size_t>& which) {
  std::vector<align::LocalAlignment> alignments;
  std::vector<double> path_scores, e_values;
  for (std::size_t k : which) {
    alignments.push_back(std::move(result.alignments[k]));
    path_scores.push_back(result.path_scores[k]);
    e_values.push_back(result.e_values[k]);
  }
  result.alignments = std::move(alignments);
  result.path_scores = std::move(path_scores);
  result.e_values = std::move(e_values);
}

// Per pair: the probability that its alignment is a revisit (significance::revisit_probability of its E-value),
// times the pair's posterior within its alignment (align/pair_posterior.hpp), with lambda from the statistics (1
// without them: the scores are then log-odds as they stand). A pair of a masked frame has no posterior of its own
// (its scores are flat): it stands where the evidence on either side puts it, as sure as the less sure of the two,
// and less where the two passes cross the stretch in different numbers of frames.
void add_confidences(const align::ScoreSource& scores, const align::AlignConfig& engine, const MapConfig& c,
                     const MapDecisions& d, const std::vector<bool>& masked, const detail::UnmaskedFrames& unmasked,
                     MapResult& result) {
  align::PosteriorConfig pc;
  pc.lambda = d.statistics.valid() ? d.statistics.lambda : 1.0;
  pc.gap_a = engine.gap_a;
  pc.gap_b = engine.gap_b;
  pc.band = std::max<std::size_t>(c.confidence_band, static_cast<std::size_t>(std::ceil(d.frames_per_place)));
  pc.self = true;
  pc.min_separation = c.search.min_separation;
  // Right within the tolerance the evaluation of place recognition uses, or a place when that is wider.
  pc.tolerance = std::max(c.confidence_tolerance, static_cast<std::size_t>(std::lround(d.frames_per_place)));
  result.posteriors.assign(result.alignments.size(), {});
  // Only the alignments that contributed pairs: the others are not in the outputs' pairs.
  std::vector<bool> needed(result.alignments.size(), false);
  for (const auto& p : result.pruning.pairs) needed[p.alignment] = true;
  // Given that the row is on the revisit (the change point of alignment_ends.hpp kept it there): where along it,
  // the posterior within the tolerance over the posterior anywhere in the band. Unconditioned, a pair near an end
  // is only as sure as a chain is to reach it at all, about 1/2 for the last pairs of a revisit however clear their
  // partner (the corridor's whole revisit right, its confidences 0.45-1: expected calibration error 0.13).
  align::PosteriorConfig wide = pc;
  wide.tolerance = pc.band;
  // `scores` are those of the frames the alignment kept: each alignment's pairs of them get their posteriors there.
  const auto kept = [&](const std::pair<std::size_t, std::size_t>& p) {
    return unmasked.keeps(p.first) && unmasked.keeps(p.second);
  };
  for (std::size_t k = 0; k < result.alignments.size(); ++k) {
    if (!needed[k]) continue;
    const align::LocalAlignment seen = unmasked.to_unmasked(result.alignments[k]);
    std::vector<double> posteriors(seen.pairs.size(), 0.0);
    if (!seen.pairs.empty()) {
      posteriors = align::pair_posteriors(seen, scores, pc);
      const std::vector<double> covered = align::pair_posteriors(seen, scores, wide);
      for (std::size_t t = 0; t < covered.size(); ++t) {
        if (covered[t] > 0) posteriors[t] = std::min(1.0, posteriors[t] / covered[t]);
      }
    }
    auto& out = result.posteriors[k];
    out.assign(result.alignments[k].pairs.size(), 0.0);
    for (std::size_t t = 0, u = 0; t < out.size(); ++t) {
      if (kept(result.alignments[k].pairs[t])) out[t] = posteriors[u++];
    }
    if (!masked.empty()) detail::posteriors_through_masked(result.alignments[k], masked, pc.tolerance, out);
  }
  // A skipped image listed with the pairs (consistent_labels.hpp, Gaps): where the chains put its row.
  std::map<std::size_t, std::vector<align::RowPosterior>> rows;
  const auto row_posterior = [&](const RetainedPair& p) {
    auto it = rows.find(p.alignment);
    if (it == rows.end()) {
      const align::LocalAlignment seen = unmasked.to_unmasked(result.alignments[p.alignment]);
      std::vector<align::RowPosterior> found;
      if (!seen.pairs.empty()) found = align::row_posteriors(seen, scores, pc);
      for (auto& r : found) {  // in the frames' indices, still ascending
        r.row = unmasked.frame(r.row);
        r.col = unmasked.frame(r.col);
      }
      it = rows.emplace(p.alignment, std::move(found)).first;
    }
    const auto row = std::lower_bound(it->second.begin(), it->second.end(), p.i,
                                      [](const align::RowPosterior& r, std::size_t i) { return r.row < i; });
    const bool near =
        row != it->second.end() && row->row == p.i && std::max(row->col, p.j) - std::min(row->col, p.j) <= pc.tolerance;
    return near ? row->posterior : 0.0;
  };
  for (auto& p : result.pruning.pairs) {
    const auto& pairs = result.alignments[p.alignment].pairs;
    const auto at = std::lower_bound(pairs.begin(), pairs.end(), std::pair{p.i, std::size_t{0}});
    const double posterior = at != pairs.end() && at->first == p.i && at->second == p.j
                                 ? result.posteriors[p.alignment][static_cast<std::size_t>(at - pairs.begin())]
                                 : row_posterior(p);
    const double e = p.alignment < result.e_values.size() ? result.e_values[p.alignment] : std::nan("");
    p.confidence = (std::isfinite(e) && c.significance.max_e_value
                        ? significance::revisit_probability(e, *c.significance.max_e_value)
                        : 1.0) *
                   posterior;
  }
}

}  // namespace

TopologyConfig topology_settings(const MapConfig& c) {
  TopologyConfig topology = c.graph.topology;
  if (c.graph.clean) {
    topology.reduce_transitive = true;
    // Branch points closer than the shortest revisit cannot be told apart by an alignment between them.
    if (topology.junction_region == 0) {
      topology.junction_region = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(c.min_revisit_places)));
    }
  }
  return topology;
}

TableFit fit_table_statistics(const align::ScoreSource& scores, const MapConfig& config, double frames_per_place) {
  FitRun fit = fit_looking_further(scores, config, frames_per_place);
  fit.statistics.area = significance::search_area(scores.rows(), scores.cols(), true, config.search.min_separation,
                                                  config.search.reverse);
  TableFit out{fit.statistics, fit.chance_length, fit.global_rate};
  out.logarithmic = phase_checks(fit, config, fit.statistics.area / (frames_per_place * frames_per_place)).logarithmic;
  return out;
}

void check_map_config(const MapConfig& c) {
  const auto require = [](bool ok, const char* field, const char* range) {
    if (!ok) throw std::invalid_argument(fmt::format("MapConfig.{} must be {}", field, range));
  };
  const auto finite_at_least = [](double v, double low) { return std::isfinite(v) && v >= low; };
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  require(finite_at_least(c.search.gap, 0), "search.gap", ">= 0");
  require(!c.search.cap || positive(*c.search.cap), "search.cap", "> 0");
  require(positive(c.cap_factor), "cap_factor", "> 0");
  require(!c.significance.max_e_value || positive(*c.significance.max_e_value), "significance.max_e_value", "> 0");
  require(finite_at_least(c.significance.threshold, 0), "significance.threshold", ">= 0");
  require(finite_at_least(c.min_revisit_places, 0), "min_revisit_places", ">= 0");
  require(std::isfinite(c.score.contrast_offset), "score.contrast_offset", "finite");
  require(positive(c.phase.contrast_offset_step), "phase.contrast_offset_step", "> 0");
  require(std::isfinite(c.phase.max_contrast_offset), "phase.max_contrast_offset", "finite");
  require(!c.phase.max_global_rate || std::isfinite(*c.phase.max_global_rate), "phase.max_global_rate", "finite");
  require(!c.frames_per_place || finite_at_least(*c.frames_per_place, 1), "frames_per_place", ">= 1");
  require(positive(c.labels.max_visit_span), "labels.max_visit_span", "> 0");
  require(c.fit_alignments > 0, "fit_alignments", ">= 1");
}

namespace {

// MapConfig::drop_blind_descriptors: the similarities that see no revisit (ascending; empty when the check does not
// apply or none is blind). Blind: its own map has no loop closure, another's has one at E <= max_e_value / D
// (choosing among D descriptors is a test each, Bonferroni: a chance alignment of one descriptor on a sequence
// without a revisit is not made the map more often than the fusion's own would be), and on that map's pairs its
// enhanced scores are no higher than on the rest of the search, within 3 standard errors. The last condition
// keeps a descriptor too weak to map alone that still adds evidence (a simulated figure-eight: the joint
// histogram alone finds nothing, but scores the panorama signature's pairs 0.63 above its chance cells, t = 11,
// and the fusion maps better than either).
// The check enhances each similarity; it leaves them in `enhanced` (one per similarity, or none when the check
// does not apply), for the fusion not to enhance them again.
std::vector<std::size_t> blind_descriptors(const std::vector<SimilarityMatrix>& similarities, const MapConfig& c,
                                           std::size_t contrast_window, std::span<const Pose2> odometry,
                                           const std::vector<bool>& masked,
                                           std::span<const std::size_t> low_information,
                                           std::vector<SimilarityMatrix>& enhanced) {
  const std::size_t n = similarities.front().rows;
  if (!c.drop_blind_descriptors || similarities.size() < 2 || !c.significance.max_e_value || contrast_window == 0 ||
      n > c.max_blind_check_frames) {
    return {};
  }
  const double strict = *c.significance.max_e_value / static_cast<double>(similarities.size());
  std::vector<std::size_t> unseeing;
  std::vector<std::pair<std::size_t, std::size_t>> seen;  // the pairs of the maps that see at `strict`
  MapConfig quiet = c;  // each map alone tells nothing of its own steps: the check's progress is the maps done
  quiet.progress = {};
  // One pass at a time: the exact engine's N x N table of one direction, not two, beside the similarities
  // enhanced so far (the peak stays the fused map's).
  quiet.threads = 1;
  if (c.progress) c.progress("descriptors mapped alone", 0, similarities.size());
  for (std::size_t k = 0; k < similarities.size(); ++k) {
    const SimilarityMatrix& e = enhanced.emplace_back(enhanced_one(similarities[k], contrast_window));
    const MapResult alone = build_map_from_enhanced(align::ScoreSource::dense(e.values, e.rows, e.cols), quiet,
                                                    odometry, {}, low_information);
    if (c.progress) c.progress("descriptors mapped alone", k + 1, similarities.size());
    if (alone.pruning.pairs.empty()) unseeing.push_back(k);
    bool sees = false;
    for (const auto& p : alone.pruning.pairs) sees |= alone.e_values[p.alignment] <= strict;
    if (sees) {
      for (const auto& p : alone.pruning.pairs) seen.emplace_back(p.i, p.j);
    }
  }
  if (seen.size() < 2 || unseeing.size() == similarities.size()) return {};
  std::vector<std::size_t> blind;
  for (std::size_t k : unseeing) {
    // The scores as the map's alignment sees them: soft-masked (detail::soft_mask).
    const auto e = [&, &scores = enhanced[k], ceiling = c.score.contrast_offset](std::size_t i, std::size_t j) {
      return !masked.empty() && (masked[i] || masked[j]) ? std::min(scores(i, j), ceiling) : scores(i, j);
    };
    double chance = 0;
    std::size_t cells = 0;
    for (std::size_t i = c.search.min_separation; i < n; ++i) {
      for (std::size_t j = 0; j + c.search.min_separation <= i; ++j) chance += e(i, j), ++cells;
    }
    chance /= static_cast<double>(std::max<std::size_t>(cells, 1));
    double sum = 0, sum2 = 0;
    for (const auto& [i, j] : seen) sum += e(i, j), sum2 += static_cast<double>(e(i, j)) * e(i, j);
    const auto m = static_cast<double>(seen.size());
    const double mean = sum / m, sd = std::sqrt(std::max(0.0, sum2 / m - mean * mean));
    if (mean - chance < 3 * sd / std::sqrt(m)) blind.push_back(k);
  }
  return blind;
}

}  // namespace

MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config, std::span<const Pose2> odometry) {
  return build_map(std::vector<SimilarityMatrix>{similarity}, config, odometry);
}

namespace {

// The steps of build_map, with the frames flagged in `masked` (empty: none) soft-masked.
MapResult build_map_masked(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config,
                           std::span<const Pose2> odometry, const std::vector<bool>& masked) {
  const auto start = std::chrono::steady_clock::now();
  if (similarities.empty() || similarities.front().empty()) throw std::invalid_argument("empty similarity matrix");
  check_map_config(config);
  check_similarities(similarities);
  MapConfig c = config;
  const bool estimate = (config.unit == align::Unit::places) && !config.frames_per_place;
  std::optional<PlaceScale> scale;
  if (estimate) {
    // The travelled distance when there is odometry (a smooth descriptor can look alike over many places);
    // else the decay of the similarity along the sequence.
    scale = place_scale(odometry, [&] { return frames_per_place(similarities); });
    c.frames_per_place = scale->frames_per_place;
  }
  const MapConfig framed = settings_in_frames(c, c.frames_per_place.value_or(1.0));
  const double place_frames =
      (c.unit == align::Unit::places) ? c.frames_per_place.value_or(1.0) : 1.0;  // frames a place spans
  const std::size_t hub_k = framed.score.contrast_window > 0 && c.hubness_neighbours > 0
                                ? places_in_frames(c.hubness_neighbours, place_frames)
                                : 0;
  std::vector<SimilarityMatrix> corrected;
  if (hub_k > 0) {
    corrected = similarities;
    for (auto& s : corrected) similarity::correct_hubness(s, hub_k, framed.search.min_separation);
  }
  const std::vector<SimilarityMatrix>& source = hub_k > 0 ? corrected : similarities;
  const std::vector<std::size_t> low_information =
      framed.score.contrast_window > 0 ? detail::flagged_frames(masked) : std::vector<std::size_t>{};
  std::vector<SimilarityMatrix> each;  // each similarity enhanced, when the blind check has done it
  const std::vector<std::size_t> blind =
      blind_descriptors(source, c, framed.score.contrast_window, odometry, masked, low_information, each);
  const auto told_enhanced = [&c](std::size_t done, std::size_t total) {
    if (c.progress) c.progress("similarities enhanced", done, total);
  };
  std::vector<std::size_t> seeing;  // the similarities fused: those not blind
  for (std::size_t k = 0; k < source.size(); ++k) {
    if (!std::binary_search(blind.begin(), blind.end(), k)) seeing.push_back(k);
  }
  SimilarityMatrix enhanced = fused(
      seeing.size(),
      [&](std::size_t d) {
        const std::size_t k = seeing[d];
        return each.empty() ? enhanced_one(source[k], framed.score.contrast_window) : std::move(each[k]);
      },
      told_enhanced);
  each.clear();
  const double seconds_scores = seconds_since(start);
  MapResult result = build_map_from_enhanced(align::ScoreSource::dense(enhanced.values, enhanced.rows, enhanced.cols),
                                             c, odometry, {}, low_information);
  result.decisions.similarities = similarities.size();
  result.decisions.blind_descriptors = blind;
  result.decisions.frames_per_place_estimated = estimate;
  result.decisions.place_scale_missing = scale && !scale->found;
  // What was aligned: the enhanced scores minus the offset the run chose (or S itself without enhancement).
  if (framed.score.contrast_window > 0) {
    for (auto& v : enhanced.values) v -= result.decisions.contrast_offset;
    const auto& aligned_masked = result.decisions.low_information_frames;  // with the tandem repeats
    if (!aligned_masked.empty())
      detail::soft_mask(enhanced, significance::frame_flags(aligned_masked, enhanced.rows), 0.0F);
  }
  result.scores = std::move(enhanced);
  result.seconds_align += seconds_scores;
  return result;
}

}  // namespace

MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config,
                    std::span<const Pose2> odometry) {
  return build_map_masked(similarities, config, odometry, {});
}

MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config,
                    std::span<const Pose2> odometry, std::span<const std::size_t> low_information) {
  if (similarities.empty() || similarities.front().empty()) throw std::invalid_argument("empty similarity matrix");
  const std::vector<bool> masked = significance::frame_flags(low_information, similarities.front().rows);
  return build_map_masked(similarities, config, odometry, config.mask_low_information ? masked : std::vector<bool>{});
}

MapResult build_map_from_enhanced(const align::ScoreSource& enhanced, const MapConfig& config,
                                  std::span<const Pose2> odometry, const AlignmentRun& run_alignment,
                                  std::span<const std::size_t> low_information_given) {
  const std::size_t n = enhanced.rows();
  if (n == 0 || enhanced.cols() != n) {
    throw std::invalid_argument("score source must be square and non-empty, got " + std::to_string(n) + " x " +
                                std::to_string(enhanced.cols()));
  }
  if (!odometry.empty() && odometry.size() != n) {
    throw std::invalid_argument("odometry has " + std::to_string(odometry.size()) + " poses, the sequence " +
                                std::to_string(n) + " images");
  }
  check_map_config(config);
  MapResult result;
  auto& d = result.decisions;
  auto start = std::chrono::steady_clock::now();
  d.frames_per_place = (config.unit == align::Unit::places) ? config.frames_per_place.value_or(1.0) : 1.0;
  const MapConfig c = settings_in_frames(config, d.frames_per_place);
  d.contrast_window = c.score.contrast_window;
  d.min_separation = c.search.min_separation;
  d.min_revisit_pairs = c.significance.max_e_value ? places_in_frames(c.min_revisit_places, d.frames_per_place) : 0;
  // Without contrast enhancement the scores are S itself, aligned as given (the paper): no offset.
  float offset = c.score.contrast_window > 0 ? c.score.contrast_offset : 0.0F;
  align::AlignConfig engine = align_config(c);

  // Frames of little information carry no evidence of a revisit (with contrast enhancement, unless
  // mask_low_information is off), in the statistics' fit as in the alignment; nor do tandem repeats of appearance
  // (significance/tandem_repeats.hpp), found here from the scores whatever computed them (dense or streamed).
  std::vector<std::size_t> low_information;
  if (config.mask_low_information && c.score.contrast_window > 0) {
    low_information.assign(low_information_given.begin(), low_information_given.end());
    if (c.search.min_separation > 4) {
      significance::TandemRepeatConfig rc;
      // Periods up to the band (twice one fits in twice the band): a longer one is a revisit the band lets through.
      rc.reach = 2 * c.search.min_separation;
      rc.min_frames = c.search.min_separation;
      rc.half_window = std::max<std::size_t>(c.search.min_separation / 2, 2);
      rc.near = std::clamp<std::size_t>(places_in_frames(2.0, d.frames_per_place), 2, c.search.min_separation / 2);
      const std::vector<std::size_t> in_repeats = significance::tandem_repeat_frames(enhanced, rc);
      const std::size_t given = low_information.size();
      std::vector<std::size_t> merged;
      std::set_union(low_information.begin(), low_information.end(), in_repeats.begin(), in_repeats.end(),
                     std::back_inserter(merged));
      d.tandem_repeat_frames = merged.size() - given;
      low_information = std::move(merged);
    }
  }
  const std::vector<bool> masked =
      low_information.empty() ? std::vector<bool>{} : significance::frame_flags(low_information, n);
  // The statistics' fit, the alignment and the posteriors leave out long stretches of frames of little information
  // and see the other masked frames soft-masked (detail::UnmaskedFrames).
  const std::vector<bool> left_out =
      masked.empty()
          ? std::vector<bool>{}
          : detail::long_stretches(significance::frame_flags(low_information_given, n), c.search.min_separation);
  const detail::UnmaskedFrames unmasked(n, left_out);
  const std::vector<bool> masked_in_view = unmasked.of_view(masked);
  const auto aligned = [&](const align::ScoreSource& s) {
    return detail::soft_masked(unmasked.view(s), masked_in_view);
  };
  const std::size_t aligned_n = unmasked.size();
  // The cells the alignment searches (the frames it sees, both directions, the band left out).
  const double area = significance::search_area(aligned_n, aligned_n, true, c.search.min_separation, c.search.reverse);
  if (c.significance.max_e_value && aligned_n > 0) {
    const double area_places = area / (d.frames_per_place * d.frames_per_place);
    FitRun fit;
    const double bound = c.phase.max_global_rate.value_or(0.0F);
    // One fit per offset tried, of at most this many (the progress' total; the loop ends at the first in the
    // logarithmic phase).
    const bool adapting = c.phase.adapt_offset && c.score.contrast_window > 0;
    const std::size_t fits =
        adapting ? 1 + static_cast<std::size_t>(std::max(
                           0.0F, (c.phase.max_contrast_offset - offset) / c.phase.contrast_offset_step + 1e-6F))
                 : 1;
    std::size_t fitted = 0;
    while (true) {
      fit = fit_looking_further(aligned(minus(enhanced, offset)), c, d.frames_per_place);
      if (c.progress) c.progress("statistics' fits", std::min(++fitted, fits), fits);
      const auto [short_chance, logarithmic] = phase_checks(fit, c, area_places);
      if (logarithmic || !fit.statistics.valid() || !c.phase.adapt_offset || c.score.contrast_window == 0 ||
          offset + c.phase.contrast_offset_step > c.phase.max_contrast_offset + 1e-6F) {
        if (c.progress) c.progress("statistics' fits", fits, fits);
        if (!logarithmic && fit.statistics.valid())
          d.linear_phase.push_back({offset, short_chance, fit.global_rate, bound, fit.chance_length, std::nullopt});
        break;
      }
      d.linear_phase.push_back(
          {offset, short_chance, fit.global_rate, bound, fit.chance_length, offset + c.phase.contrast_offset_step});
      offset += c.phase.contrast_offset_step;
    }
    d.statistics = fit.statistics;
    // K is per cell: a fit on diagonal blocks of a long sequence counts the chance alignments of the whole
    // search (the chance agreement below keeps the fit's own area: which of its alignments are chance).
    d.statistics.area = area;
    d.chance_length = fit.chance_length;
    d.chance_mean = fit.cell_mean;
    if (fit.statistics.valid()) {
      if (!odometry.empty() && c.odometry.gate && c.odometry.evidence) {
        d.odometry_chance_agreement = chance_agreement(fit, odometry, *c.odometry.gate);
      }
      // On a grid of 1/64 score units, which both engines represent exactly (the fast engine's scale is a power
      // of two of at least 64 for caps up to 512), so they agree on what is significant.
      const auto grid = [](double v) { return static_cast<float>(std::ceil(std::max(v, 1.0 / 64) * 64.0) / 64.0); };
      engine.threshold = grid(d.statistics.score_at(*c.significance.max_e_value / d.odometry_chance_agreement));
      // The cap from the score's own significance: the odometry does not change how far chance extends a path.
      if (c.cap_from_statistics) {
        engine.cap = grid(c.cap_factor * grid(d.statistics.score_at(*c.significance.max_e_value)));
        // Masking takes the look-alike chance alignments of dark frames out of the fit, so its tail is lighter
        // and the cap lower than the sequence as recorded gives: never lower than that, so a revisit that runs
        // through a weak stretch beside a tunnel stays one (Nordland's frames 127-182, winter against summer).
        // "As recorded" is the sequence the alignment sees: the long stretches it leaves out are not in it (dark
        // stretches aligned with each other raised the cap past a revisit's weak last frames).
        if (!masked.empty()) {
          const FitRun recorded = fit_looking_further(unmasked.view(minus(enhanced, offset)), c, d.frames_per_place);
          if (recorded.statistics.valid()) {
            engine.cap = std::max(*engine.cap,
                                  grid(c.cap_factor * grid(recorded.statistics.score_at(*c.significance.max_e_value))));
          }
        }
      }
      // What the filter removed: chance alignments of the statistics' run above the raw threshold.
      for (std::size_t k = 0; k < fit.alignments.size(); ++k) {
        const double e = d.statistics.e_value(fit.path_scores[k]);
        if (e * d.odometry_chance_agreement > *c.significance.max_e_value &&
            fit.alignments[k].score >= c.significance.threshold) {
          result.insignificant.push_back(unmasked.to_frames(fit.alignments[k]));
          result.insignificant_e_values.push_back(e);
        }
      }
    } else {
      // The fixed threshold and cap were chosen for one frame per place; scores grow with the frames per place.
      engine.threshold = static_cast<float>(c.significance.threshold * d.frames_per_place);
      if (c.search.cap) engine.cap = static_cast<float>(*c.search.cap * d.frames_per_place);
      d.unfitted_chance_alignments = fit.fitted;
    }
  }
  d.contrast_offset = offset;
  d.cap = engine.cap;
  d.score_threshold = engine.threshold;

  const auto searched = static_cast<std::size_t>(area);
  std::function<void(std::size_t, std::size_t)> told_cells;
  if (c.progress) {
    told_cells = [progress = c.progress](std::size_t done, std::size_t total) {
      progress("cells aligned", done, total);
    };
  }
  const align::ScoreSource scores =
      remembering_cells(told_progress(aligned(minus(enhanced, offset)), searched, told_cells));
  auto found = aligned_n == 0  ? std::vector<align::LocalAlignment>{}
               : run_alignment ? run_alignment(engine, offset, left_out, masked)
               : c.alignment_set == align::AlignmentSet::locally_optimal
                   ? (c.search.reverse ? align::locally_optimal_alignments_both(scores, engine, c.threads)
                                       : align::locally_optimal_alignments(scores, engine))
                   : run_engine(scores, engine, c.engine, c.search.reverse, c.threads);
  if (told_cells && searched > 1) told_cells(searched, searched);
  for (auto& a : found) {
    const double path = align::path_score(a, scores, c.search.gap, c.search.gap);
    const double e = d.statistics.valid() ? d.statistics.e_value(path) : std::nan("");
    if (a.pairs.size() < d.min_revisit_pairs) {
      result.insignificant.push_back(unmasked.to_frames(std::move(a)));
      result.insignificant_e_values.push_back(e);
      continue;
    }
    result.alignments.push_back(std::move(a));
    result.path_scores.push_back(path);
    result.e_values.push_back(e);
  }
  if (c.trim_chance_ends && d.statistics.valid()) {
    // A tail a chance extension reaches with probability 5 % or more.
    const double max_tail_gain = std::log(20.0) / d.statistics.lambda;
    const std::size_t before = pair_count(result.alignments);
    for (auto& a : result.alignments) {
      a = significance::trim_chance_ends(a, scores, c.search.gap, c.search.gap, d.chance_mean, max_tail_gain);
    }
    d.trimmed_chance_end_pairs = before - pair_count(result.alignments);
  }
  if (c.significance.max_e_value && engine.cap) {
    select_alignments(result, realign_in_bands(result.alignments, scores, engine, c.search.gap,
                                               places_in_frames(significance::kShadowReach, d.frames_per_place)));
  }
  if (!low_information.empty()) {
    for (auto& a : result.alignments) a = unmasked.to_frames(std::move(a));
    select_alignments(result, detail::through_masked_frames(result.alignments, masked));
    d.low_information_frames.assign(low_information.begin(), low_information.end());
  }
  // Most significant first: capped scores tie at the cap, their paths' scores do not. Pruning and labels
  // then prefer the strongest of overlapping alignments (parallel shadows of one revisit, crossing chances).
  std::vector<std::size_t> order(result.alignments.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return result.path_scores[x] > result.path_scores[y]; });
  select_alignments(result, order);
  if (!odometry.empty() && c.odometry.gate) {
    const std::vector<OdometryVerdict> verdicts = odometry_verdicts(result.alignments, odometry, *c.odometry.gate);
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < verdicts.size(); ++k) {
      if (verdicts[k] == OdometryVerdict::consistent) {
        kept.push_back(k);
      } else {
        result.rejected.push_back(std::move(result.alignments[k]));  // not selected below
        result.rejected_verdicts.push_back(verdicts[k]);
      }
    }
    select_alignments(result, kept);
    // Every alignment left agrees with the odometry: that is evidence too (MapConfig::odometry.evidence), weighed
    // by how well it agrees. Those the evidence does not carry below max_e_value are not significant.
    if (d.odometry_chance_agreement < 1) {
      const std::vector<double> r = odometry_agreement(result.alignments, odometry, *c.odometry.gate);
      std::vector<std::size_t> significant;
      for (std::size_t k = 0; k < r.size(); ++k) {
        result.e_values[k] *= std::min(1.0, d.odometry_chance_agreement / std::exp(-0.5 * r[k] * r[k]));
        if (result.e_values[k] <= *c.significance.max_e_value) {
          significant.push_back(k);
        } else {
          result.insignificant.push_back(result.alignments[k]);
          result.insignificant_e_values.push_back(result.e_values[k]);
        }
      }
      select_alignments(result, significant);
    }
    const std::size_t before = pair_count(result.alignments);
    result.alignments = trim_to_odometry(result.alignments, odometry, *c.odometry.gate);
    d.trimmed_odometry_pairs = before - pair_count(result.alignments);
  }
  result.seconds_align = seconds_since(start);

  start = std::chrono::steady_clock::now();
  std::vector<PlaceLabel> labels;
  if (c.labels.method == LabelSettings::Method::consistent) {
    ConsistentLabellingConfig lc;
    lc.min_separation = c.search.min_separation;
    lc.max_visit_span = places_in_frames(c.labels.max_visit_span, d.frames_per_place);
    lc.left_out = left_out;
    auto labelling =
        label_consistently(n, result.alignments, result.path_scores, lc, c.labels.pruning.min_retained_fraction);
    result.pruning = std::move(labelling.accepted);
    labels = std::move(labelling.labels);
  } else {
    result.pruning = prune_per_column(result.alignments, c.labels.pruning);
    std::vector<std::pair<std::size_t, std::size_t>> same_place;
    same_place.reserve(result.pruning.pairs.size());
    for (const auto& p : result.pruning.pairs) same_place.emplace_back(p.i, p.j);
    labels = label_places(n, same_place);
  }
  const TopologyConfig topology = topology_settings(c);
  if (c.graph.clean) {
    GraphCleanupConfig cleanup;
    cleanup.min_separation = c.search.min_separation;
    // Nothing shorter than the shortest revisit can be told apart from the place beside it.
    const std::size_t shortest = std::max<std::size_t>(1, places_in_frames(c.min_revisit_places, d.frames_per_place));
    cleanup.max_tip_frames = shortest;
    cleanup.max_bubble_frames = shortest;
    cleanup.session_starts = c.graph.topology.session_starts;
    labels = clean_graph(labels, result.alignments, result.pruning, cleanup).labels;
  }
  result.map = build_topology(labels, result.alignments, result.pruning, topology);
  result.seconds_prune_label = seconds_since(start);

  start = std::chrono::steady_clock::now();
  add_confidences(scores, engine, c, d, masked, unmasked, result);
  describe_junctions(result.map, result.alignments, result.pruning, topology);  // with the pairs' confidences
  result.seconds_confidence = seconds_since(start);
  return result;
}

MapResult build_map_from_scores(const align::ScoreSource& scores, const MapConfig& config,
                                std::span<const Pose2> odometry) {
  MapConfig c = config;
  c.score.contrast_window = 0;  // the scores are aligned as they are
  c.unit = align::Unit::frames;
  return build_map_from_enhanced(scores, c, odometry);
}

}  // namespace seqtopo::mapping
