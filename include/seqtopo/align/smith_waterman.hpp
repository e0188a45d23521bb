#pragma once
// All non-intersecting local alignments of A and B, best first (Smith-Waterman with Waterman-Eggert
// declumping), with the mapping paper's cap on the cumulative score.
//
// Recurrence over the grid graph, cell (i, j) = best score of an alignment ending with A[i-1], B[j-1]:
//   H(i, j) = min(cap, max(0, H(i-1, j-1) + S(i-1, j-1), H(i-1, j) - gap_a, H(i, j-1) - gap_b))
//
// Declumping: once an alignment is taken, none of its aligned pairs may be aligned again (a diagonal
// step into such a cell is forbidden; gaps may still pass through it). Only the cells whose value
// changes are recomputed (they lie below and to the right of the alignment's first pair).
//
// Choice rules, stated because ties are common with a cap (a matching stretch is a plateau at the cap):
//  * next alignment: the highest cell; among equal scores the one with the largest i, then largest j
//    (in the pass's own coordinates), so a capped plateau is taken at its far end, whole;
//  * traceback: prefer the diagonal step, then the vertical (gap in B), then the horizontal step.
//
// Worked example (match +2, mismatch -1, gap 1), A = "abedx", B = "ecdab":
//   the best alignment is A[2..4) = "ed" with B[0..3) = "ecd": e-e (+2), gap over c (-1), d-d (+2) = 3.
// Memory: one float per cell and one byte per cell for the used pairs. Time: one full fill, then work
// proportional to the changed region per alignment.
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// One pass (config.direction). Throws std::invalid_argument on a negative or NaN gap or cap, or a
// self alignment of a non-square source.
std::vector<LocalAlignment> local_alignments(const ScoreSource& scores, const AlignConfig& config = {});

// Forward and reverse passes (run concurrently when threads > 1; the result does not depend on it),
// merged best first: by score, then forward before reverse, then by a_begin, b_begin. The two passes
// are independent, so a forward and a reverse alignment may share a pair where they cross.
std::vector<LocalAlignment> local_alignments_both(const ScoreSource& scores, AlignConfig config = {},
                                                  unsigned threads = 2);

}  // namespace seqtopo::align
