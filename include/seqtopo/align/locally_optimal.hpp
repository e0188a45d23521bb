#pragma once
// All locally optimal alignments (mapping paper, section IV-B, after Schmidt 1998 and Sellers 1984), with the
// paper's cap on the cumulative score: the set the paper asks for. The engine of smith_waterman.hpp reports
// instead the Waterman-Eggert set, in which no two alignments share an aligned pair; here alignments may
// share pairs, start or end cells: every path that no shortening and no extension improves is reported.
//
// Grid graph of one pass (the same cells, directions and self-alignment triangle as local_alignments()):
// vertex (i, j), 0 <= i <= m, 0 <= j <= n; a diagonal step into (i, j) pairs A[i-1] with B[j-1] (B read
// backwards in the reverse pass) and weighs S; a vertical step weighs -gap_a, a horizontal one -gap_b. A step
// may only enter a vertex of the searched region (all of them, or one triangle for a self alignment).
//
// Score of a path P with steps w_1 .. w_k (k >= 1), the engine's cumulative score: r_0 = 0,
// r_t = min(cap, r_{t-1} + w_t), score(P) = r_k (without a cap: the sum of the weights).
// P is admissible when r_t > 0 for every t >= 1: the engine's recurrence never restarts inside it. The cap
// therefore decides how much evidence carries across a non-matching stretch (a stretch of weight <= -cap
// always ends an admissible path), which is why two revisits separated by such a stretch stay apart.
//
// Definition. An admissible path P from u to v is locally optimal when
//  (1) it scores at least as much as each of its sub-paths: score(P) >= score(Q) for every contiguous
//      piece Q of P (each scored from 0 on its own);
//  (2) it scores strictly more than every admissible path that contains it: score(P) > score(R) for every
//      admissible R != P of which P is a contiguous piece;
//  (3) it is a highest scoring admissible path from u to v, and the canonical one: the path that takes, from
//      v backwards, the first tight step in the order diagonal, vertical, horizontal (a step into x is tight
//      when the best admissible score at its tail, 0 at u, followed by the step gives the best admissible
//      score at x), so that its score at every vertex is the best admissible score there.
// (1) and (2) are Sellers' and Schmidt's conditions (no sub-path is better, every enclosing path is worse)
// with the capped score; (3) is Schmidt's "highest scoring path" between two vertices with a tie rule.
// The strict > in (2) and the > 0 in admissibility settle ties: a stretch that nets zero is not included at
// the start (the path starts after it) but is included at the end (the longer path is taken), and a capped
// plateau is taken whole. Without a cap this is the classical definition on sums (admissible = every prefix
// positive).
//
// What the conditions come to, and how they are computed (the implementation; the tests check the
// definition itself by enumerating every path of small grids):
//  * (2) at the start: no admissible path ends at u, i.e. the local_alignments() table H is 0 at u
//    (without declumping); at the end: no non-empty path from v, started at score(P), stays positive and
//    returns to score(P) or above.
//  * (1): the score at the end is the maximum of the scores along the path.
//  * Each start u with H(u) = 0 and a positive diagonal step out of it seeds one sparse fill of the best
//    admissible scores from u, over the cells where they stay positive; each cell of it that passes the
//    tests ends one locally optimal alignment.
//
// Relation to the non-intersecting set: the best score is the same (the maximum of H; tested). A strong
// revisit usually appears here with near copies that start or end a few cells away, sharing pairs with it
// (the paper prunes them per column, section IV-C); a non-intersecting alignment found after others were
// declumped need not be locally optimal, and a locally optimal one that crosses a better one is not in the
// non-intersecting set.
//
// Cost: one float per cell for the scores of the pass and one byte per cell for H (O(N^2) memory, 52 + 13 MB
// for N = 3,600), and per start the cells where its scores stay positive: about N^2 in all on noise, and up
// to a revisit's length times its band (cap / gap wide) for each of the starts along it. Without a cap the
// bands are not bounded and long revisits cost much more.
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// Which set of local alignments an engine reports.
//  non_intersecting: Waterman-Eggert declumping, no two alignments share an aligned pair (smith_waterman.hpp)
//  locally_optimal: every locally optimal alignment as defined above
enum class AlignmentSet { non_intersecting, locally_optimal };
std::string_view to_string(AlignmentSet set);
// "non-intersecting" or "locally-optimal"; throws std::invalid_argument naming both otherwise.
AlignmentSet parse_alignment_set(std::string_view text);

// One pass (config.direction), best first: by score, then a_begin, b_begin, a_end, b_end. Scores at least
// config.threshold (and > 0), at most config.max_alignments. Throws std::invalid_argument like
// local_alignments().
std::vector<LocalAlignment> locally_optimal_alignments(const ScoreSource& scores, const AlignConfig& config = {});

// Both passes (concurrently when threads > 1; the result does not depend on it), merged by merge_directions().
std::vector<LocalAlignment> locally_optimal_alignments_both(const ScoreSource& scores, AlignConfig config = {},
                                                            unsigned threads = 2);

}  // namespace seqtopo::align
