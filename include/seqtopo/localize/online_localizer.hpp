#pragma once
// Online localization: query frames arrive one at a time, each as its row of similarities against the
// whole map, and after each one the current best map position is known from the frames seen so far.
//
// Definition. The localizer runs the forward and the reverse Smith-Waterman recurrences of the alignment
// engine (smith_waterman.hpp, same gap, cap and row scoring as localize_sequence) one query row at a
// time, keeping only the previous row of each table:
//   F(i, j) = min(cap, max(0, F(i-1, j-1) + s(i, j), F(i-1, j) - gap, F(i, j-1) - gap))
//   R(i, j) = min(cap, max(0, R(i-1, j+1) + s(i, j), R(i-1, j) - gap, R(i, j+1) - gap))
// where s is the row-scored similarity (score_row). F(i, j) is the best alignment of query frames up to i
// ending on the pair (i, j) with the map driven forwards, R the same driven backwards. After frame i the
// best guess is the cell of row i with the highest value v over both tables (ties: the higher row score
// s(i, j), then forward before reverse, then the smaller j). These rows are exactly the rows of the engine's
// first fill on the query frames seen so far, before any declumping, so they never change when later
// frames arrive: the guess of frame i is final when it is made. (The offline localize_sequence uses the
// whole query, later frames included, and so may differ.)
//
// Confidence, as offline (localize.hpp): the probability that the guess is within `tolerance` map frames of the
// truth, P(revisit | E) x posterior. E is the E-value of the guess's alignment (its path up to the path's highest
// value P; P = v while the path rises, see below) in the search so far:
// the extreme-value fit of the declumped alignments of the frames seen (significance/score_statistics.hpp, as
// localize_sequence fits them), made again each time the frames seen double from kFirstFit up to kFitFrames, then
// every kFitFrames frames on the last kFitFrames rows, its area scaled to the whole search so far. A fit whose lambda
// is more than twice Karlin & Altschul's of the cells (which bounds the gapped one of chance alignments from above) is
// not used: the first frames' chance alignments, too few to show their tail, gave lambda 4-90 on Nordland where the
// cells give 1.3, and made every alignment significant. The posterior is where in row i the alignment ends, given that
// one does: the weight exp(lambda F) of the alignment ends (cells reached by a matched pair, not by a gap) within
// +-tolerance of the guess in its table over that of every alignment end of both tables. Before a fit P(revisit | E) is
// 1 when v >= `threshold` and 0 below, and lambda is Karlin & Altschul's of the scores seen
// (significance::ungapped_lambda), as offline without a fit. The frame is "in the map" when the confidence is at least
// `min_confidence`.
//
// Past the end of a revisit (the query leaves the map, or drives on past the map's last frame) the table keeps the
// alignment's value for as many frames as the evidence takes to fall, and a chance matched pair now and then ends a
// path there again. As offline, where a local alignment ends at its maximum, the guess's alignment is its path up to
// the path's highest value P (E is that of P). A frame past P is on it with the odds exp(-lambda D) : 1/m of the path
// going on against its end at P (m map frames: the end a priori anywhere along the map), where D is what the path's
// gaps cost since P, at most P - v: the confidence is multiplied by 1 / (1 + exp(lambda D) / m). Only the gaps count:
// a path that stops matching (the map ends, the route leaves it) pays a gap a frame, while a path through weak frames
// that still match in order (a stretch of poor light) loses little to them and is still the route (on Nordland a
// weak stretch 70 frames long is 23 below its maximum and right all along). A frame that raises its path's maximum
// (D = 0) is on the alignment. Measured in docs/results.md (mode parity).
//
// Several descriptors (the constructor's `descriptors`): each frame's rows are fused as offline (fused_score_row)
// with the weights descriptor_weights gives on the frames seen, made again at each refit; when they change the
// tables are replayed with them.
//
// Fixed-lag smoothing (config.lag = L > 0; Anderson & Moore, Optimal Filtering, 1979, ch. 7): the frame L frames
// back is answered with the evidence of the L frames since. Its cell (i, j) scores the best alignment
// through it, G(i, j) = F(i, j) + C(i, j): the table value (the best alignment of the frames up to i ending there)
// plus the best continuation of that alignment into the later frames, C(i, j) = max(0, Q(i + 1, j + 1)) with the
// suffix recurrence of the same scores and gaps run backwards from the last frame,
//   P(r, j) = s(r, j) + max(0, Q(r + 1, j + 1)),   Q(r, j) = max(P(r, j), Q(r + 1, j) - gap, Q(r, j + 1) - gap)
// (mirrored in j for the reverse table; the continuation is uncapped). The guess, E-value and posterior are those
// above with G in place of F, so with no later frame (C = 0) the answer is the frame's own estimate. The history
// behind the filter is kept whole (F carries it), unlike a localization of a window of recent frames, which
// loses a revisit through a stretch of weak frames. Work: O(L x map frames) a frame; memory: L + 1 rows of each table.
//
// Work per frame: O(map frames x descriptors), plus the refits (a localization of at most kFitFrames rows, D + 1 with
// several descriptors, at 8, 16, ..., 256, 512, 768, ... frames: a bounded latency at those frames). Memory: the rows
// seen, for the refits (frames x map frames floats, and as many again per descriptor with several).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/localize/localize.hpp"

namespace seqtopo::localize {

struct OnlineEstimate {
  std::size_t query = 0;          // index of the frame just fed
  bool in_map = false;            // confidence >= min_confidence
  std::size_t map = 0;            // best guess of the map frame now, given for every frame
  float score = 0;                // the table value there (capped alignment score ending at this frame)
  double confidence = 0;          // the probability that the guess is right (see above)
  double e_value = std::nan("");  // of the score in the search so far (NaN before a fit)
  align::Direction direction = align::Direction::forward;
};

class OnlineLocalizer {
 public:
  static constexpr std::size_t kFirstFit = 8;     // frames seen at the first fit of the statistics
  static constexpr std::size_t kFitFrames = 256;  // the refits' rows: doubling up to it, then every kFitFrames

  // `descriptors` similarities a frame, fused as offline (localize_sequence of several matrices): their weights
  // (descriptor_weights) from the frames seen, made again at each refit. Throws std::invalid_argument on
  // map_frames == 0, descriptors == 0 or an unusable config.
  OnlineLocalizer(std::size_t map_frames, const LocalizeConfig& config = {}, std::size_t descriptors = 1);

  // Feeds the next query frame's similarities to every map frame (map_frames values, finite): one descriptor.
  OnlineEstimate feed(std::span<const float> similarity_row);
  // The same with one row per descriptor. `low_information`: the frame is a dark or near-uniform image
  // (significance/low_information.hpp): every score of it at most 0, as offline (LowInformationFrames).
  OnlineEstimate feed_descriptors(std::span<const std::span<const float>> similarity_rows,
                                  bool low_information = false);
  // The map frames of little information (sorted; before the first frame): their scores at most 0, as offline.
  // Throws std::invalid_argument for a frame outside the map or after the first feed.
  void set_low_information_map(std::span<const std::size_t> frames);

  // The estimate of frame `frame` with the evidence of every frame seen since (see fixed-lag smoothing above): any of
  // the last config.lag + 1 frames. smoothed(frames_seen() - 1) is the estimate feed returned for the last frame.
  // Throws std::out_of_range for a frame not seen or further back.
  OnlineEstimate smoothed(std::size_t frame) const;

  std::size_t map_frames() const { return map_frames_; }
  std::size_t frames_seen() const { return frames_seen_; }
  // The table rows of the last frame (map_frames values each), for inspection and tests.
  std::span<const float> forward_row() const { return now_.forward.values; }
  std::span<const float> reverse_row() const { return now_.reverse.values; }
  // The statistics the confidences use now (valid() false before the first fit).
  const significance::ScoreStatistics& statistics() const { return fit_; }
  // The descriptors' weights in the fusion now (empty: equal, before the first fit or with one descriptor).
  const std::vector<double>& weights() const { return weights_; }

 private:
  // One frame's row of a table, and per cell: whether an alignment ends there on a matched pair (1), the highest
  // value on its path (its alignment's score: a local alignment ends at its maximum) and what the path's gaps cost
  // since that value.
  struct Table {
    explicit Table(std::size_t cells = 0)
        : values(cells, 0.0F), ends(cells, 0), peaks(cells, 0.0F), gaps(cells, 0.0F) {}
    std::vector<float> values;
    std::vector<std::uint8_t> ends;
    std::vector<float> peaks, gaps;
  };
  // One frame's rows: the two tables' and its scored row.
  struct Rows {
    Table forward, reverse;
    std::vector<float> scores;
  };

  void step();               // the recurrences' next rows from now_.scores
  OnlineEstimate advance();  // step, then the estimate of the frame
  void refit();              // the weights, statistics and lambda from the rows seen
  // The estimate of a frame from its rows and, per cell, the score the alignment gains after it (empty: none).
  OnlineEstimate estimate(std::size_t frame, const Rows& rows, std::span<const float> forward_after,
                          std::span<const float> reverse_after) const;

  std::size_t map_frames_;
  LocalizeConfig config_;
  std::size_t frames_seen_ = 0;
  Rows now_;                                   // the last frame's rows
  Table previous_forward_, previous_reverse_;  // the tables' rows before them
  std::vector<Rows> history_;       // the last config.lag + 1 frames' rows, oldest first, for the fixed-lag smoothing
  std::vector<float> seen_;         // the scored rows so far, for the refits
  std::vector<bool> map_masked_;    // per map frame: of little information (empty: none)
  std::vector<bool> query_masked_;  // per query frame seen: of little information
  std::vector<std::vector<float>> raw_;  // several descriptors: each one's similarity rows so far
  std::vector<double> weights_;
  std::vector<float> scratch_;
  significance::ScoreStatistics fit_;
  double lambda_ = 1.0;
  std::size_t next_fit_ = 1;  // frames seen at the next refit (doubling)
};

// The online estimates of every frame of a whole query matrix, computed in one go: the reference the online
// localizer must equal, and a causal (filtering) alternative to localize_sequence.
std::vector<OnlineEstimate> online_estimates(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});

}  // namespace seqtopo::localize
