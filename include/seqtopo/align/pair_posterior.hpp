#pragma once
// How sure is each pair of a local alignment: the posterior probability that images i and j are aligned, by
// posterior decoding (Durbin, Eddy, Krogh & Mitchison, "Biological Sequence Analysis", 1998, ch. 4.4; the
// partition-function form of Smith-Waterman, Miyazawa 1995, as probabilistic aligners such as ProbCons use).
//
// Model: a local alignment is a chain of matched pairs (i1 < i2 < ..., j1 < j2 < ... forward; j decreasing for
// a reverse alignment) weighted exp(lambda * score), score = sum of the pairs' scores minus gap_a for every
// element of A and gap_b for every element of B skipped between consecutive pairs, the score the engine
// maximises. With lambda from the significance statistics (significance/score_statistics.hpp) lambda * score
// is a log-odds. The partition function sums every chain (and the empty one, "no alignment here"); the
// posterior of (i, j) is the weight of the chains through it over the total. Between two consecutive pairs
// the skipped elements of A are counted before those of B, so each chain is counted once.
//
// The sum runs over a band of +-band cells around the alignment's path, from `band` rows before its first
// pair to `band` rows after its last, so it stays linear in the alignment's length. A pair that stands out
// from its neighbourhood gets a posterior near 1; a pair where a shifted path or a gap scores about as well
// (the drifting end of a revisit, an image unlike its partner inside a long alignment) gets less.
#include <cstddef>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

struct PosteriorConfig {
  double lambda = 1;  // [1 / score unit]
  double gap_a = 1.5, gap_b = 1.5;
  std::size_t band = 8;  // [cells] either side of the path, and rows before and after it
  // Self alignment: cells with i - j < min_separation (both passes: i > j) are outside every chain.
  bool self = false;
  std::size_t min_separation = 0;
  // The posterior of a pair (i, j) counts i aligned to any j' within +-tolerance of j: with images a place
  // apart looking alike, the chains share i's partner between neighbouring columns that are all right.
  std::size_t tolerance = 0;
};

// One posterior per pair of `alignment`, in its order, each in [0, 1]. Throws std::invalid_argument when a pair
// lies outside `scores` or lambda is not positive.
std::vector<double> pair_posteriors(const LocalAlignment& alignment, const ScoreSource& scores,
                                    const PosteriorConfig& config);

// Posterior decoding of every row of the band (the alignment's rows, and `band` rows before its first pair and
// after its last): where the chains put the row. A chain puts row i at column j when it pairs them, or when it
// skips i between two pairs, the one before at column j (a traversal slower than the other repeats frames:
// its row between two matched ones is still at the earlier one's place). The row's most probable column and
// the posterior within +-tolerance of it. Rows the band leaves no cell in are left out. Beyond the alignment's ends
// this is where a chain extending it would most likely put the row, with the probability that one does: how
// localization reaches the ends of a revisit the alignment's own maximum stopped short of.
struct RowPosterior {
  std::size_t row = 0, col = 0;
  double posterior = 0;
};
std::vector<RowPosterior> row_posteriors(const LocalAlignment& alignment, const ScoreSource& scores,
                                         const PosteriorConfig& config);

}  // namespace seqtopo::align
