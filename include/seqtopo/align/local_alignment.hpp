#pragma once
// Results and settings of the local-alignment engine (mapping paper, section IV-B).
#include <cstddef>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// forward: A[i] pairs with B[j] and both indices grow together (a path revisited in the same direction).
// reverse: A is aligned against B read backwards; along the alignment i grows while j shrinks
// (a path revisited in the opposite direction: an anti-diagonal line in the score matrix).
enum class Direction { forward, reverse };
std::string_view to_string(Direction direction);

struct AlignConfig {
  // Penalty for each element of A matched to a gap (a vertical step in the grid graph) [score units].
  Score gap_a = 1.0F;
  // Penalty for each element of B matched to a gap (a horizontal step).
  Score gap_b = 1.0F;
  // Upper bound on the cumulative score (the paper's cap). Without it: classical Smith-Waterman.
  std::optional<Score> cap;
  // Only alignments whose score is at least this are reported (and always > 0).
  Score threshold = 0.0F;
  // Stop after this many alignments (best first).
  std::size_t max_alignments = std::numeric_limits<std::size_t>::max();
  Direction direction = Direction::forward;
  // A and B are the same sequence: only pairs (i, j) with i - j >= min_separation are searched, so
  // the trivial self-match and the frames around it never count, and every pair is found once.
  bool self = false;
  std::size_t min_separation = 1;
};

struct LocalAlignment {
  Score score = 0;  // the (capped) cumulative score at the alignment's last cell
  Direction direction = Direction::forward;
  // Half-open ranges in the original indices of A and B, spanning the aligned pairs.
  std::size_t a_begin = 0, a_end = 0, b_begin = 0, b_end = 0;
  // Aligned (matched or mismatched) pairs (i, j) in original indices, in increasing i.
  // Elements skipped by a gap are in the ranges but not in the pairs.
  std::vector<std::pair<std::size_t, std::size_t>> pairs;

  friend bool operator==(const LocalAlignment&, const LocalAlignment&) = default;
};

// The alignment cut to its pairs [first, last] (indices into `pairs`, first <= last < pairs.size()), the ranges
// spanning them again; score and direction as they were (trimming a revisit's ends keeps its evidence).
LocalAlignment pairs_between(const LocalAlignment& alignment, std::size_t first, std::size_t last);

// The score of an alignment's own path, with no cap: the sum of its pairs' scores minus a gap penalty for every
// element skipped between consecutive pairs (gap_a per skipped element of A, gap_b of B). For a capped alignment
// this is the evidence the cap hides; for an uncapped one it equals the engine's score.
double path_score(const LocalAlignment& alignment, const ScoreSource& scores, double gap_a, double gap_b);

}  // namespace seqtopo::align
