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
// estimate is the cell of row i with the highest value over both tables (ties: the higher row score
// s(i, j), then forward before reverse, then the smaller j); its value is the confidence, and the frame is
// "not in the map" while that value is below `threshold`. These rows are exactly the rows of the engine's
// first fill on the query frames seen so far, before any declumping, so they never change when later
// frames arrive: the estimate of frame i is final when it is made. (The offline localize_sequence uses the
// whole query, later frames included, and so may differ.)
//
// Work and memory per frame: O(map frames), independent of how many frames have been seen.
#include <cstddef>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/localize/localize.hpp"

namespace seqtopo::localize {

struct OnlineEstimate {
  std::size_t query = 0;  // index of the frame just fed
  bool in_map = false;    // confidence >= threshold
  std::size_t map = 0;    // best map frame now
  float confidence = 0;   // the table value there (capped alignment score ending at this frame)
  align::Direction direction = align::Direction::forward;
};

class OnlineLocalizer {
 public:
  // Throws std::invalid_argument on map_frames == 0 or an unusable config.
  OnlineLocalizer(std::size_t map_frames, const LocalizeConfig& config = {});

  // Feeds the next query frame's similarities to every map frame (map_frames values, finite).
  OnlineEstimate feed(std::span<const float> similarity_row);

  std::size_t map_frames() const { return map_frames_; }
  std::size_t frames_seen() const { return frames_seen_; }
  // The table rows of the last frame (map_frames values each), for inspection and tests.
  std::span<const float> forward_row() const { return forward_; }
  std::span<const float> reverse_row() const { return reverse_; }

 private:
  std::size_t map_frames_;
  LocalizeConfig config_;
  std::size_t frames_seen_ = 0;
  std::vector<float> forward_, reverse_, previous_forward_, previous_reverse_, scores_;
};

// The online estimates of every frame of a whole query matrix, computed in one go: the reference the online
// localizer must equal, and a causal (filtering) alternative to localize_sequence.
std::vector<OnlineEstimate> online_estimates(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});

}  // namespace seqtopo::localize
