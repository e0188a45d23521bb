#pragma once
// Frames of little information in a map (MapConfig::mask_low_information): their scores soft-masked, their pairs
// placed between the evidence on either side.
#include <cstddef>
#include <string>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::mapping::detail {

// `scores` with every cell in a masked row or column at most 0, read a row segment at a time (`masked` empty or
// all false: `scores` itself).
align::ScoreSource soft_masked(const align::ScoreSource& scores, const std::vector<bool>& masked);

// Every cell in a masked row or column at most `ceiling` (0 for aligned scores: the same as soft_masked), so
// such a frame neither adds evidence nor is made into a revisit, and an alignment can still run through it. The
// cells below the ceiling keep their value: a dark frame facing a daylit one is still evidence against a revisit
// there. `masked` empty: nothing.
void soft_mask(SimilarityMatrix& enhanced, const std::vector<bool>& masked, float ceiling);

// The alignments with the pairs of masked frames placed along the straight line between the nearest pairs of
// unmasked frames before and after them (their scores are flat, so where the path runs inside a masked stretch is
// the tie-breaking's choice, not evidence), and those at either end, with evidence on one side only, cut off. Returns
// the indices of the alignments that keep a pair of unmasked frames (an alignment of masked frames alone is none).
std::vector<std::size_t> through_masked_frames(std::vector<align::LocalAlignment>& alignments,
                                               const std::vector<bool>& masked);

// The posteriors (one per pair of `alignment`) of its pairs of masked frames: the smaller of the nearest pairs'
// with evidence before and after, times min(1, (2 tolerance + 1) / (|di - dj| + 1)) where the passes cross the
// stretch in di and dj frames. Pairs outside any such stretch keep theirs.
void posteriors_through_masked(const align::LocalAlignment& alignment, const std::vector<bool>& masked,
                               std::size_t tolerance, std::vector<double>& posteriors);

}  // namespace seqtopo::mapping::detail
