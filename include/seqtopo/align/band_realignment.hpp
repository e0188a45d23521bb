#pragma once
// The path a capped alignment should have taken, found again in a band around it.
//
// Once a path reaches the cap its score stops growing, so on the plateau every neighbouring diagonal that is
// also positive ties with it, and which of them the traceback follows — and where it steps from one to the
// next — is a matter of tie-breaking, not of evidence. In a smooth sequence, or one recorded at a low frame
// rate, the band of similar diagonals around a revisit is several frames wide: the traceback may leave on the
// diagonal beside the revisit's own, or zig-zag between its neighbours, and loop closures are then frames off.
// The uncapped path score is the evidence the cap hid. Re-aligning the same rows without the cap, in a band of
// `reach` columns either side of the engine's path, recovers the path the evidence supports: banded alignment
// (Chao, Pearson & Miller 1992), as read mappers polish a hit in a band around it (Li & Durbin 2009, BWA).
#include <cstddef>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// The best path, by path score (the pairs' scores minus gap_a for every row and gap_b for every column skipped
// between consecutive pairs; no cap), from a pair in the alignment's first row to a pair in its last row, whose
// every cell lies within `reach` columns of the engine's path in its row (a row the path skips: the column of
// the pair before) and inside the cells `search` searches (a self search: i - j >= min_separation). Reverse
// alignments keep their direction (j falls as i grows). The alignment itself when no path in the band scores
// more than its own; ties between new paths go to pairs (diagonal steps) before gaps, rows before columns, and
// to the end nearest the engine's. Score (the engine's, capped) and direction are kept.
LocalAlignment realign_in_band(const LocalAlignment& alignment, const ScoreSource& scores, const AlignConfig& search,
                               std::size_t reach);

}  // namespace seqtopo::align
