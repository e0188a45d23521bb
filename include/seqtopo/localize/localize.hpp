#pragma once
// Sequence-based localization of a query traverse inside a mapped one (the kidnapped robot with a camera):
// the query x map similarity matrix is aligned with the local-alignment engine of the mapping paper
// (section IV-B, forward and reverse passes, cap, Waterman-Eggert declumping) and every query frame takes its
// map frame from the alignments that cover it.
//
// Orientation: rows are query frames, columns map frames (as in baseline/seqslam.hpp), so the query is
// sequence A of the engine and the map is B. A query driven along the map in the opposite direction is
// an anti-diagonal line and is found by the reverse pass.
//
//   SimilarityMatrix s = ...;                       // query x map, higher = more similar
//   LocalizeResult r = localize_sequence(s);        // r.frames[q].map, .score, .covered
//
// Scores. Each row is first contrast-enhanced (score_matrix): every cell becomes its z-score against the
// cells of the same row within +-contrast_window map frames, minus `contrast_offset`. The alignment then rewards a
// cell that stands out of its neighbourhood by more than `contrast_offset` standard deviations and penalises the
// rest, whatever the scale of the similarity (kappa drops out). Row-local, so the online localizer can do
// the same with one row at a time.
//
// Speed. A query recorded at another speed than the map is a path that is not at 45 degrees: every map
// frame skipped (faster) or every query frame repeated on one map frame (slower) costs one gap. The path still
// pays while a matched frame gains more than the gaps per frame cost, e.g. at half speed gain > gap.
//
// Per-frame result. A query frame is covered when it lies in the query range of an alignment scoring at
// least `threshold`. Its map frame is the alignment's partner of that frame (for a frame skipped by a gap,
// the partner interpolated between the neighbouring pairs). Its score is the alignment's own score gained
// within +-score_window query frames around it (cell scores of the pairs there minus the gaps there), so a
// long alignment that wanders off the true path for a while gets a low score exactly there. Among several
// covering alignments the one with the higher local score wins; the others are the frame's runner-up
// candidates (for recall@5). A frame that no alignment covers is "not in the map" - a normal result.
#include <cstddef>
#include <optional>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::localize {

struct LocalizeConfig {
  // Row contrast enhancement (similarity/contrast_enhancement.hpp): z-score against +-contrast_window map
  // frames (0 = the whole row; see score_matrix).
  std::size_t contrast_window = 10;
  bool enhance = true;            // false: the similarity is used as given (minus contrast_offset)
  float contrast_offset = 0.75F;  // subtracted after enhancement [standard deviations]
  float gap = 2.0F;               // gap penalty, both directions [score units]
  std::optional<float> cap;       // upper bound on the cumulative score (mapping paper); nullopt = none
  float threshold = 10.0F;        // minimum alignment score for an alignment to cover frames
  bool reverse = true;            // also search the map driven backwards
  std::size_t max_alignments = 1000;
  std::size_t score_window = 10;  // [query frames] half-width of the per-frame score window
  std::size_t candidates = 5;     // best map frames kept per query frame (for recall@k)
  unsigned threads = 1;           // forward and reverse passes in parallel when > 1; result does not depend on it
};

struct FrameMatch {
  bool covered = false;  // false = "not in the map"
  std::size_t map = 0;   // best map frame (meaningful when covered)
  float score = 0;       // local alignment score around this frame (higher = more confident)
  align::Direction direction = align::Direction::forward;
  std::vector<std::size_t> candidates;  // best first, distinct alignments; candidates[0] == map when covered
};

struct LocalizeResult {
  std::vector<FrameMatch> frames;                 // one per query frame (row)
  std::vector<align::LocalAlignment> alignments;  // every alignment found, best first (a = query, b = map)
};

// The matrix the alignment scores: contrast-enhanced rows minus the contrast offset (see above). Throws
// std::invalid_argument on an empty matrix or non-finite values.
SimilarityMatrix score_matrix(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});
// One row of it (the online localizer's path); identical to the matrix version's row.
void score_row(const float* similarity_row, std::size_t cols, const LocalizeConfig& config, float* out);

// Throws std::invalid_argument on an empty matrix, non-finite values or a negative/NaN setting.
LocalizeResult localize_sequence(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});

// Per-frame result from alignments already found on `scores` (the matrix the alignments scored): the
// second half of localize_sequence, exposed for callers that run the engine themselves.
std::vector<FrameMatch> frames_from_alignments(const std::vector<align::LocalAlignment>& alignments,
                                               const SimilarityMatrix& scores, const LocalizeConfig& config);

// The single-image baseline: each query frame takes the most similar map frame (ties: the smaller index);
// score = that similarity, candidates = the `candidates` most similar map frames. Every frame is covered.
std::vector<FrameMatch> single_frame_matches(const SimilarityMatrix& query_x_map, std::size_t candidates = 5);

// Throws std::invalid_argument naming the problem when the config is unusable.
void validate(const LocalizeConfig& config);

}  // namespace seqtopo::localize
