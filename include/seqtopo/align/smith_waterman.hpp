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
// Choice rules, stated because ties are common (small integer scores; with a cap, a matching stretch
// is a plateau of cells at the cap). They follow Huang & Miller's SIM (EMBOSS matcher), so the
// alignments, not only their scores, agree with it. A step into a cell is "tight" if it attains the
// cell's (positive) value; an optimal alignment ending at a cell is a path of tight steps.
//  * end: the first maximal cell in row-major order (smallest i, then smallest j, in the pass's own
//    coordinates). If that maximum is the cap, the end is instead the last maximal cell (row-major)
//    reachable from it by tight steps, so a capped plateau is taken at its far end, whole (SIM would
//    stop at its near end).
//  * start: of all optimal alignments ending there, the one whose start (the zero cell before its
//    first pair) is latest: largest i, then largest j. Leading stretches that net zero are dropped.
//  * path between start and end, by recursive bisection as in SIM's linear-space traceback: the path
//    crosses the middle row of the current rectangle (top + height / 2, rounded down) at the leftmost
//    column an optimal path can use, except that it crosses at the rightmost column where it can
//    enter the row by a diagonal or rightward step only and leave it downwards, if there is such a
//    column right of the leftmost; a rectangle one row high takes no pair if a gap-only route is
//    optimal, else its leftmost possible pair. (With tie-free scores, e.g. real-valued similarities,
//    all of this yields the unique optimal alignment.)
//
// Worked example (match +2, mismatch -1, gap 1), A = "abedx", B = "ecdab": the best alignment is
// A[0..2) = "ab" with B[3..5) = "ab" (+2 +2 = 4); the next one that shares no pair with it is A[2..4) = "ed"
// with B[0..3) = "ecd": e-e (+2), gap over c (-1), d-d (+2) = 3.
// Memory: one float per cell and one byte per cell for the used pairs, plus one byte per cell of the
// alignment's rectangle while its path is recovered. Time: one full fill, then per alignment work
// proportional to the changed region and to its rectangle.
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

// The engines' order of alignments: best first by score, then forward before reverse, then by a_begin, b_begin
// (then a_end, b_end and the pairs, which only alignments that may share pairs need).
bool best_first(const LocalAlignment& x, const LocalAlignment& y);

// The merge of local_alignments_both (every engine's two passes use it): in best_first order, at most
// max_alignments.
std::vector<LocalAlignment> merge_directions(std::vector<LocalAlignment> forward, std::vector<LocalAlignment> reverse,
                                             std::size_t max_alignments);

// One pass of an engine over `scores` in config.direction, and both passes of it (concurrently when threads > 1;
// the result does not depend on it) merged by merge_directions().
using AlignmentPass = std::vector<LocalAlignment> (*)(const ScoreSource& scores, const AlignConfig& config);
std::vector<LocalAlignment> both_directions(AlignmentPass pass, const ScoreSource& scores, AlignConfig config,
                                            unsigned threads);

}  // namespace seqtopo::align
