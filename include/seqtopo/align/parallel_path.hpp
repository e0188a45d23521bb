#pragma once
// The parallel path a capped alignment should have taken.
//
// Once a path reaches the cap its score stops growing, so on the plateau every neighbouring diagonal that is
// also positive ties with it, and which of them the traceback follows is a matter of tie-breaking, not of
// evidence. In a smooth sequence, or one recorded at a low frame rate, the band of similar diagonals around a
// revisit is several frames wide and the traceback may leave on the diagonal beside the revisit's own: every
// loop closure is then one or more frames off. The uncapped path score is the evidence the cap hid; shifting
// the whole path sideways (the same steps, so the same gaps) to the parallel whose cells sum highest recovers
// the revisit's own diagonal. A polishing step after the search, as read mappers re-align a seed's hit in a
// band around it (Li & Durbin 2009, BWA; Myers 1999, banded re-alignment).
#include <cstddef>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// `alignment` moved by the column shift d in [-reach, reach] whose pairs' scores sum highest, among the shifts
// whose every pair stays inside the cells `search` searches (a self search: i - j >= min_separation); ties keep
// the smaller |d|, then the negative one. The score (the engine's, capped) and direction are kept.
LocalAlignment best_parallel_path(const LocalAlignment& alignment, const ScoreSource& scores, const AlignConfig& search,
                                  std::size_t reach);

}  // namespace seqtopo::align
