#pragma once
// Where a revisit ends, by a change point of the path's own scores.
//
// A local alignment ends at its best cumulative score, so past a revisit's true end it runs on while the
// chance cells beside it happen to gain a little (a few frames of noise summing to a point or two). Those
// frames are more likely chance than revisit: model each pair's score as drawn from the revisit's
// distribution (mean mu1, estimated on the alignment's own pairs) or from chance (mean mu0, the sequence's
// cells off the self band), with a common spread. For a split into revisit and chance stretches, the log
// likelihood ratio of a pair grows with (score - (mu0 + mu1) / 2), so the most likely revisit is the stretch
// of pairs that maximises the sum of score - midpoint (Page's CUSUM change point, 1954; the same rule as
// Smith-Waterman's end with every step lowered by the midpoint). Skipped elements cost their gap penalties
// as in the path's score.
#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::significance {

// The alignment cut back at either end to where the cumulative sum of (score - midpoint) minus the gap
// penalties, midpoint = (chance_mean + mean of the pairs' scores) / 2, peaks, each end only when the stretch
// cut off scores (its own cells minus its gaps) below max_tail_gain: a gain a chance extension often reaches
// (with statistics lambda, ln(20) / lambda is one reached with probability 5 %), so a dip inside a long revisit
// does not cut off the stretch after it. Unchanged when the pairs' mean is not above chance_mean, or with fewer
// than 3 pairs. a_begin..b_end span the pairs kept; the score is left as it was.
align::LocalAlignment trim_chance_ends(const align::LocalAlignment& alignment, const align::ScoreSource& scores,
                                       double gap_a, double gap_b, double chance_mean, double max_tail_gain);

}  // namespace seqtopo::significance
