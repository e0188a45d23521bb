#pragma once
// Online mapping: the frames of one sequence arrive one at a time, and after each one the loop closures,
// revisits, junctions and place merges that the frames so far support are known (docs/online.md).
//
// Definition. Frame t is compared with every earlier frame j (its descriptor's distance D(t, j), cosine or
// SAD as the offline path uses for that descriptor, S = -D: the contrast enhancement below removes kappa).
// The score of the pair is the causal contrast enhancement of S (mapping/causal_contrast.hpp: the offline
// symmetric form 0.5 (E + E^T) with the column's window one-sided) minus an offset. Pairs closer than min_separation
// frames are never scored. The forward and reverse Smith-Waterman recurrences of the offline engine
// (align/smith_waterman.hpp, its self search with min_separation, gap and cap) then get one new row each:
//   F(t, j) = min(cap, max(0, F(t-1, j-1) + s(t, j), F(t-1, j) - gap, F(t, j-1) - gap))
//   R(t, j) = min(cap, max(0, R(t-1, j+1) + s(t, j), R(t-1, j) - gap, R(t, j+1) - gap))
// for j = 0 .. t - min_separation (cells outside are 0), bit for bit the rows of the engine's first fill of
// the same scores (so they never change when later frames arrive).
//
// Significance (the island method of Olsen, Bundschuh & Hwa 1999; Altschul et al. 2001): the cells of a
// table that share one start cell form an island, and an island's score is its largest value. In the
// logarithmic phase the number of chance islands scoring at least s in `area` cells is about
// K * area * exp(-lambda s), the model the offline map fits to its declumped alignments
// (significance/score_statistics.hpp). Every island of F and R that has died (no cell of the newest row carries
// its start) joins the sample (the best `island_sample` kept), unless its best cell lies within min_separation
// columns of a loop closure of its direction in that frame: the diagonals beside a revisit score almost as well
// and are part of it (the offline fit leaves such shadows out too). After each frame lambda and K are fitted to the
// best 1/64 of the islands died so far (at most island_sample, at least 48: the tail of their distribution),
// with the area searched so far (the pairs i - j >= min_separation of frames 0 .. t, twice with the reverse
// pass), by the offline fit, which sets the few real revisits at the top aside. The threshold of the frame is
// then the score whose E-value is max_e_value (at most the cap): the expected number of chance revisits at
// least that good in the frames so far. It grows like 2 ln(t) / lambda, and the expected number of chance
// revisits reported over a whole run, frames t0 .. N, is about 2 max_e_value ln(N / t0). Until the sample is
// large enough for a fit, the offline fit of the table so far stands in (early_fit_frames); without either (and
// with max_e_value unset) the threshold is `threshold`.
//
// Events, from the rows alone:
//  * a revisit (a track) is a peak of F or R in row t that reaches the threshold (the largest value within
//    +-reach columns); a track continues from row t-1 to the peak of row t within `reach` columns of its last
//    column plus one step (forward: j + 1, reverse: j - 1). It begins when a peak reaches threshold that no
//    track continues (revisit_begin, with the alignment's start cell: each cell carries the start of the path
//    that attains it). A track whose best cell near its predicted column falls below threshold, x_drop below
//    the best it has reached, or lower or not matching (its cell not reached by a diagonal step onto a positive
//    score) `patience` frames in a row, is dormant (no loop closures) while its path lives
//    on in the table (some cell of the row still carries its start cell); it resumes when that path climbs above the
//    value it fell asleep at (and above threshold and best - x_drop; the frames it slept through get loop closures
//    along the line between its cells) and ends when the path dies out or at finish(). Its end frame is the last frame
//    at which it reached its best value.
//  * every frame of a live track is a loop closure (t, j) with the track's direction and its confidence
//    (score / cap, at most 1); when a track begins, the frames between its start and t get loop closures
//    interpolated along the line from the start cell to (t, j).
//  * loop closures after a track's end frame, and every loop closure of a track shorter than
//    min_revisit_frames, are withdrawn by a correction event: later frames overturned them.
//  * a loop closure becomes settled (never withdrawn) once its track reaches a new best at or after its frame
//    and is at least min_revisit_frames long; settled pairs join the places (union of frames). A place merge
//    is a settled pair that joins two places each of at least two frames (a third traversal linking the first
//    two).
//  * a junction is where a revisit joins the old path in its middle (begin: forward with the old frame more
//    than `reach` frames after the sequence's start; reverse with it more than min_separation + 2 reach frames
//    before the new one, i.e. not a U-turn) or leaves it in its middle (end before finish(): forward when the
//    old path continues more than `reach` frames, reverse when the old frame is more than `reach` frames from
//    the start), once per place.
//  * a revisit candidate is reported before the evidence confirms it: a peak of the row (the largest value within
//    min_separation columns, not within min_separation columns of a live track) whose score reaches the
//    score of candidate_e_value but not yet the threshold, on a path (start cell) that is not a track's
//    (revisit_candidate, once per path, with its cell, its start cell and E-value). It has no loop closures. A
//    path is known by its start cell; start cells within min_separation frames and columns of each other are one
//    path (a path re-rooted through a gap), and a candidate whose start no cell carries any longer follows the
//    best such neighbour. When a track begins on the same path, its revisit_begin names the candidate
//    (confirmed); when the path dies out first (or the run ends), a correction with the candidate's id and no loop
//    closure withdraws it. A candidate is thus the
//    earliest report of a revisit at a looser E-value, which the user thresholds: of candidates at E-value x,
//    about x chance ones in the frames so far are expected (as for revisits at max_e_value). Only once the
//    statistics are fitted (an E-value needs them).
// The loop closures still standing after finish() are the online map's loop closures (loop_closures()).
//
// Work per frame: O(t) for the distance row, the contrast sums, the two recurrences and the peaks (dense rows;
// no N x N table), plus the events. Memory: the descriptors (N x dim), three rows per table and w + 1 rows of
// S: O(N (dim + w)).
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/settings.hpp"
#include "seqtopo/core/disjoint_sets.hpp"
#include "seqtopo/mapping/causal_contrast.hpp"
#include "seqtopo/significance/online_islands.hpp"
#include "seqtopo/significance/score_statistics.hpp"
#include "seqtopo/similarity/distance.hpp"

namespace seqtopo::mapping {

struct OnlineMapConfig {
  // How add_descriptor compares two descriptors (cosine for descriptors.npy rows, sad for patch thumbnails).
  similarity::Distance distance = similarity::Distance::cosine;
  // The sections the offline map shares (align/settings.hpp), with its defaults. score.contrast_window = 0: S
  // aligned as it is (no enhancement, no offset). The contrast offset is the first tried: the logarithmic phase
  // is checked twice (docs/online.md), and where the chance paths grow with the sequence (the linear phase: no
  // threshold keeps them out) phase.adapt_offset raises it by contrast_offset_step for the frames that follow (up
  // to max_contrast_offset), live paths are rescored and the islands sampled anew:
  //  * the scores: the global alignment rate of a table drawn from the first scores
  //    (significance/alignment_phase.hpp) must not exceed phase.max_global_rate, checked from 2,048 scores on
  //    (the rates of noise and of real sequences: docs/online.md);
  //  * the islands: after each fit, their median length in places (the frames from an island's start to its best
  //    cell, over the frames per place estimated from the similarities so far, place_scale.hpp) must stay within
  //    max(4, ln(area in places)), the offline map's bound for its chance alignments; checked once a scale is
  //    found.
  // The phase is checked only for the scores the mapper enhances itself (not add_scores). A track's peak must
  // reach the score of significance.max_e_value (unset: significance.threshold always, as before the statistics
  // can be fitted).
  align::ScoreSettings score;
  align::PhaseSettings phase;
  align::SearchSettings search;
  align::SignificanceSettings significance;
  // What score.contrast_window and search.min_separation count. The online mapper estimates no scale before it
  // aligns, so Unit::places needs frames_per_place (the offline map's decisions.frames_per_place, or the user's).
  align::Unit unit = align::Unit::frames;
  std::optional<double> frames_per_place;
  // S(t, t) of the similarity rows, which they do not hold (0 for S = -distance: add_descriptor's and the image
  // rows'); unset: unknown, and the place scale is not estimated (islands are measured in frames).
  std::optional<float> self_similarity = 0.0F;
  // A revisit candidate's score must reach the score of this E-value (unset: no candidates); above
  // significance.max_e_value, and unused without it.
  std::optional<double> candidate_e_value = 1.0;
  // Until the dead islands suffice for a fit (a few hundred frames), the statistics are fitted as the offline map
  // fits them (mapping::fit_table_statistics: the declumped alignments of the table so far, kept in memory while
  // the run has at most this many frames), again each time the frames grow by an eighth; 0: never, `threshold`
  // until the islands suffice. A short run (the bundled corridor's 84 frames) then reports at its own E-value.
  std::size_t early_fit_frames = 1024;
  std::size_t island_sample = 512;     // the best chance islands kept for the fit
  std::size_t reach = 3;               // [frames] peaks and track continuation
  float x_drop = 20.0F;                // a track sleeps this far below its best [score units]
  std::size_t min_revisit_frames = 5;  // shorter tracks are withdrawn
  std::size_t patience = 3;            // a track whose value falls this many frames in a row sleeps (0: never)
};

// Throws std::invalid_argument naming the setting.
void validate(const OnlineMapConfig& config);
// The config with its windows and separations in frames (Unit::frames; unchanged when they are). Throws as
// validate does.
OnlineMapConfig settings_in_frames(const OnlineMapConfig& config);

enum class OnlineEventKind {
  loop_closure,
  revisit_begin,
  revisit_end,
  junction,
  place_merge,
  correction,
  revisit_candidate,
  // A session break inside an input, found by the pipeline from the frames' times and looks
  // (timeline/session_breaks.hpp), not by the mapper: the map's later outputs start a new session at frame i.
  session_break
};
std::string_view to_string(OnlineEventKind kind);

struct OnlineEvent {
  OnlineEventKind kind = OnlineEventKind::loop_closure;
  std::size_t frame = 0;  // the frame after which the event was emitted (0-based)
  // loop_closure: the pair (i > j); revisit_candidate: the cell (frame, old frame) that reached the candidates'
  // score, its path's start cell in first and last. revisit_begin: the start cell. revisit_end: the end cell. junction:
  // the new frame i and the old frame j where the paths join or leave. place_merge: i and j, the pair that merged.
  std::size_t i = 0, j = 0;
  align::Direction direction = align::Direction::forward;
  float score = 0;       // the table value (loop closure, begin, end: the track's)
  float confidence = 0;  // loop closure: min(1, score / cap) (score / threshold / 2 without a cap)
  // loop closure, revisit begin and end: the E-value of `score` in the frames so far (unset before a fit).
  std::optional<double> e_value;
  std::size_t revisit = 0;  // track id (0, 1, ... in order of their begin); place_merge: unused
  // revisit_begin / revisit_end: the track's first and last frames (revisit_end: `frames` long);
  // junction: true when joining (begin), false when leaving (end); place_merge: the two places' first frames.
  std::size_t first = 0, last = 0, frames = 0;
  bool joining = false;
  // correction: the loop closures withdrawn (i, j) and why.
  std::vector<std::pair<std::size_t, std::size_t>> withdrawn;
  std::string reason;
  // revisit_candidate: its id (0, 1, ... in order); revisit_begin: the candidate it confirms; correction: the
  // candidate withdrawn (no loop closure withdrawn then).
  std::optional<std::size_t> candidate;
  // session_break: the frame after the gap is i (j = i - 1); the gap in the frames' times and the recording's
  // median interval so far [s].
  double gap = 0, median_interval = 0;
};

// A loop closure still standing.
struct OnlineLoopClosure {
  std::size_t i = 0, j = 0;
  align::Direction direction = align::Direction::forward;
  float confidence = 0;
  std::size_t revisit = 0;
};

class OnlineMapper {
 public:
  explicit OnlineMapper(const OnlineMapConfig& config = {});

  // The next frame as its descriptor (every frame the same length, finite); returns the events it caused.
  std::vector<OnlineEvent> add_descriptor(std::span<const float> descriptor);
  // The next frame as its similarity S(t, j) to every earlier frame j (t values; higher = more similar):
  // contrast-enhanced as add_descriptor does.
  std::vector<OnlineEvent> add_similarity(std::span<const float> similarity_row);
  // The next frame as several similarities (one row of t values per descriptor, the same number every frame),
  // each contrast-enhanced on its own and the enhanced scores averaged, as the offline default fuses its
  // descriptors.
  std::vector<OnlineEvent> add_similarities(const std::vector<std::vector<float>>& rows);
  // The next frame as its alignment scores s(t, j), j = 0 .. t - min_separation (max(0, t - min_separation + 1)
  // values), aligned as they are: no enhancement, no offset (the engine's own view; tests and other sensors).
  std::vector<OnlineEvent> add_scores(std::span<const float> scores);
  // The next frame added is of little information (a dark or near-uniform image: significance/low_information.hpp,
  // its rule as the frames arrive): with contrast enhancement its scores, and later frames' scores with it, are at
  // most 0 once aligned (soft-masked, as the offline map masks its short stretches), so it carries no evidence of a
  // revisit and a run of them is no revisit. Without enhancement it is aligned as it scores.
  void next_frame_low_information() { next_masked_ = true; }
  // The frames so far of little information, ascending.
  std::vector<std::size_t> low_information_frames() const;
  // Ends every live track (no junction: the run ended, not the revisit) and withdraws the open candidates. Further
  // frames may still be added.
  std::vector<OnlineEvent> finish();

  std::size_t frames() const { return frames_; }
  const OnlineMapConfig& config() const { return config_; }
  // The loop closures standing now (emitted and not withdrawn), by increasing i then j.
  std::vector<OnlineLoopClosure> loop_closures() const;
  // The rows of the last frame (t - min_separation + 1 values each, empty before), for tests.
  std::span<const float> forward_row() const { return forward_; }
  std::span<const float> reverse_row() const { return reverse_; }
  std::span<const float> last_scores() const { return scores_; }
  // The threshold of the next frame (fitted after the last one), and the statistics it came from (invalid before
  // a fit).
  float threshold() const { return threshold_; }
  const significance::ScoreStatistics& statistics() const { return statistics_; }
  // Whether they came from the table so far (early_fit_frames: its declumped alignments) rather than the islands.
  bool statistics_from_table() const { return early_fitted_; }
  // The contrast offset of the next frame, and each time adapt_offset raised it.
  struct OffsetChange {
    std::size_t frame = 0;  // the last frame at the old offset
    float from = 0, to = 0;
    // "scores": the global alignment rate of the scores so far was above max_global_rate (global_rate);
    // "islands": the fitted islands' median length (chance_length, in places at frames_per_place) above the
    // logarithmic phase's bound.
    std::string check;
    double global_rate = 0;
    double chance_length = 0, bound = 0, frames_per_place = 1;
  };
  float contrast_offset() const { return offset_; }
  const std::vector<OffsetChange>& offset_changes() const { return offset_changes_; }
  // The scores of the islands that have died so far (the best island_sample of them), best first; empty
  // without max_e_value.
  std::vector<double> island_scores() const;
  // The place of every frame so far: the smallest frame of its set of settled pairs.
  std::vector<std::size_t> places();

 private:
  struct Track {
    std::size_t id = 0;
    align::Direction direction = align::Direction::forward;
    std::size_t first_i = 0, first_j = 0;  // start cell
    std::size_t last_i = 0, last_j = 0;    // the cell of the latest frame
    float best = 0;
    std::size_t best_i = 0, best_j = 0;  // the latest cell at the best value
    std::vector<std::size_t> pending;    // indices into closures_, not settled yet
    bool dormant = false;                // below the threshold while its path lives on
    float last_value = 0;                // the value at the last frame it was live
    float sleep_value = 0;               // the value it fell asleep at
    std::size_t falling = 0;             // consecutive frames its value fell
  };
  std::vector<OnlineEvent> step();
  void enhance(std::span<const float> similarity_row);
  void enhance(const std::vector<std::span<const float>>& rows);
  void check_row(std::span<const float> row, std::size_t expected, const char* what) const;
  void fill_rows();
  void update_tracks(align::Direction direction, std::vector<OnlineEvent>& events);
  void emit_closure(Track& track, std::size_t i, std::size_t j, float score, std::vector<OnlineEvent>& events);
  void settle(Track& track, std::size_t up_to, std::vector<OnlineEvent>& events);
  void end_track(Track& track, bool at_finish, std::vector<OnlineEvent>& events);
  void review_closures(std::vector<OnlineEvent>& events);  // at finish(): under the last statistics
  void add_junction(const Track& track, std::size_t i, std::size_t j, bool joining, std::vector<OnlineEvent>& events);
  float confidence(float score) const;
  std::optional<double> e_value(float score) const;
  void update_islands(align::Direction direction, significance::OnlineIslands& islands);
  bool beside_a_revisit(const significance::Island& island, align::Direction direction) const;
  void update_threshold();
  void find_candidates(align::Direction direction, std::vector<OnlineEvent>& events);
  // Withdraws the candidates of `direction` whose path no cell of the newest row carries (`live`: the row's islands);
  // every one with nullptr (the run ended).
  void drop_candidates(align::Direction direction, const significance::IslandRow* live,
                       std::vector<OnlineEvent>& events);

  OnlineMapConfig config_;
  std::size_t frames_ = 0;
  std::size_t dim_ = 0;
  std::vector<float> descriptors_;  // frames_ x dim_
  std::vector<double> norms_;       // their squared norms (cosine)
  std::vector<float> similarity_;   // S of the current frame (t values)
  CausalContrast contrast_;         // the enhanced rows (without the offset)
  std::size_t channels_ = 0;
  std::vector<float> scores_;  // s(t, j), j <= t - min_separation
  std::vector<bool> masked_;   // per frame so far: of little information
  bool next_masked_ = false;   // next_frame_low_information() was called
  std::vector<float> forward_, reverse_, previous_forward_, previous_reverse_;
  // Start cell (frame, column) of the path attaining each cell, for the same rows.
  std::vector<std::uint64_t> forward_start_, reverse_start_, previous_forward_start_, previous_reverse_start_;
  std::vector<Track> tracks_;  // live tracks
  std::size_t next_track_ = 0;
  struct Closure {
    std::size_t i, j, revisit;
    align::Direction direction;
    float confidence;
    bool withdrawn;
  };
  std::vector<Closure> closures_;                                           // standing, in emission order
  OnlineEvent closure_event(OnlineEventKind kind, const Closure& c) const;  // kind, frame, pair, direction, revisit
  std::unordered_map<std::size_t, float> revisit_best_;  // the best score of each ended revisit, by id
  DisjointSets<std::size_t> places_;  // frames joined by settled pairs; a place is named by its first frame
  std::vector<std::size_t> junction_places_;
  std::map<std::uint64_t, std::size_t> ended_starts_;  // start cell of an ended track -> its last frame
  // Islands: the best value so far of each start cell in the newest row, per table; the sample of dead islands'
  // scores (a min-heap of at most island_sample values) and the fit.
  significance::OnlineIslands forward_islands_, reverse_islands_;
  // The columns of the loop closures emitted at each frame (withdrawn ones too), with their direction: islands
  // beside them are the revisit's shadows, not chance.
  std::unordered_map<std::size_t, std::vector<std::pair<std::size_t, align::Direction>>> closure_columns_;
  // The sample: (score, length in frames) of the best dead islands, a min-heap by score.
  significance::BestIslands sample_;
  std::size_t sample_from_ = 0;  // islands that started before this frame stay out (an earlier offset's)
  float offset_ = 0;
  std::vector<OffsetChange> offset_changes_;
  // S(i, i + k) for k = 1 .. kScaleLags of the first frames, per similarity: the place scale.
  std::vector<std::vector<std::vector<float>>> lag_samples_;
  double frames_per_place_ = 1;
  std::optional<std::size_t> scale_at_;  // the frame of the last estimate
  bool scale_found_ = false;
  // The enhanced scores (without the offset) of the first frames, for the global alignment rate.
  std::vector<float> phase_cells_;
  std::size_t phase_checked_at_ = 0;  // cells at the last check
  void sample_lags(const std::vector<std::span<const float>>& rows);
  void update_place_scale();  // frames_per_place_ and scale_found_, again each time the frames grow by a quarter
  // `fitted`: the (score, length) of the islands the fit took, best first.
  void check_phase(const std::vector<std::pair<double, double>>& fitted);
  void check_scores_phase();
  void raise_offset(OffsetChange change);
  bool sample_changed_ = false;
  significance::ScoreStatistics statistics_;
  float threshold_ = 0;
  // The aligned scores of the first early_fit_frames frames, row after row (as at the current offset), for the
  // fit before the islands suffice; statistics_ came from it (early_fitted_), next due at next_early_fit_ frames.
  std::vector<float> early_cells_;
  std::size_t next_early_fit_ = 0;
  bool early_fitted_ = false;
  void fit_early(double area);
  // Revisit candidates not yet confirmed or withdrawn: their ids by their path's start cell and direction.
  using Candidates = std::map<std::pair<std::uint64_t, align::Direction>, std::size_t>;
  Candidates candidates_;
  // A live track of `direction` follows the path of `start`, or its column is within min_separation of j.
  bool near_a_track(align::Direction direction, std::uint64_t start, std::size_t j) const;
  // Start cells within min_separation frames and columns of each other: one path, re-rooted through a gap.
  bool near_cells(std::uint64_t a, std::uint64_t b) const;
  // The open candidate of `direction` whose start cell is near `start` (the first), or end().
  Candidates::iterator near_candidate(std::uint64_t start, align::Direction direction);
  std::size_t next_candidate_ = 0;
};

}  // namespace seqtopo::mapping
