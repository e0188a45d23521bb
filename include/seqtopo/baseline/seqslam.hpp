#pragma once
// A SeqSLAM-style sequence search (Milford & Wyeth 2012), the baseline users of sequence place
// recognition know: local contrast enhancement of the similarity matrix, then for every query frame
// the best straight-line sequence of fixed length through earlier frames, over a range of velocities.
// Matches are accepted with a single threshold on that sequence score; there is no alignment, no
// gap handling and no reverse traversal.
#include <cstddef>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::baseline {

struct SeqSlamConfig {
  std::size_t sequence_length = 10;  // [frames] the query frame and the ones before it
  float min_velocity = 0.8F;         // database frames per query frame
  float max_velocity = 1.25F;
  std::size_t velocity_steps = 5;
  std::size_t contrast_window = 10;  // [frames] half-width of the contrast-enhancement window (0 = none)
  // Self mode (loop closure in one sequence): only database frames j <= i - min_separation.
  bool self = false;
  std::size_t min_separation = 10;
  unsigned threads = 0;  // 0 = all cores; the result does not depend on it
};

struct SequenceMatch {
  std::size_t query = 0;  // row of the similarity matrix
  std::size_t match = 0;  // best column
  float score = 0;        // mean contrast-enhanced similarity along the best line (higher = better)
  bool valid = false;     // false when no column is admissible (e.g. too early in self mode)
};

// Rows are query frames, columns database frames (or both the same sequence in self mode).
std::vector<SequenceMatch> seqslam_matches(const SimilarityMatrix& similarity, const SeqSlamConfig& config = {});

}  // namespace seqtopo::baseline
