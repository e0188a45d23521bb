#pragma once
// Per-column pruning (mapping paper, IV-C): in each column of the dynamic-programming table only the
// pairs of the longest matching subsequence are kept, which removes the inconsistent alignments that
// would otherwise make transitive labeling merge whole stretches into one place.
//
// Exact rules:
//  * A column is an image j of B (for a self alignment: the earlier image of each pair, j < i).
//  * An alignment covers column j when b_begin <= j < b_end, whether or not it has a pair in that
//    column (a gap over j still claims it: the longer alignment says j was skipped, so a shorter
//    alignment pairing j is not trusted there).
//  * In each column one covering alignment wins. The paper keeps "the longest matching subsequence"
//    (Rank::length_then_score: most pairs, then higher score). The default ranks by score first and
//    uses length to break ties (Rank::score_then_length): with the score cap, every confident
//    alignment saturates at the cap, so among those the longest still wins as in the paper, but a
//    long, weak alignment through aliased stretches can no longer take the columns of a confident
//    one (measured on the simulator's figure-eight, where that happens). Remaining ties go to the
//    earlier alignment in the input order (the engine's best-first order).
//  * Every pair (i, j) of a non-winning alignment in column j is dropped. An alignment may thus lose
//    only some of its pairs; it counts as kept when at least min_retained_fraction of its pairs
//    survive (and at least one does). Pairs of alignments that are not kept are dropped as well, so
//    no fragment of a mostly pruned alignment is left behind.
#include <cstddef>
#include <map>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::mapping {

struct PruningConfig {
  enum class Rank { score_then_length, length_then_score };
  Rank rank = Rank::score_then_length;
  double min_retained_fraction = 0.5;
};

struct RetainedPair {
  std::size_t i = 0, j = 0;   // image indices, i > j for a self alignment
  std::size_t alignment = 0;  // index into the alignment list
  float score = 0;            // that alignment's score
  // P(the pair is a revisit): exp(-E-value of the alignment) x the pair's posterior (map_builder.hpp); 1 before
  // it is computed.
  double confidence = 1;
  friend bool operator==(const RetainedPair&, const RetainedPair&) = default;
};

struct PruningResult {
  std::vector<bool> kept;                   // one per alignment
  std::vector<std::size_t> retained_count;  // pairs of each alignment that survived
  std::vector<RetainedPair> pairs;          // surviving pairs, ordered by (alignment, i)
};

PruningResult prune_per_column(const std::vector<align::LocalAlignment>& alignments, const PruningConfig& config = {});

// The first and the last retained pair (smallest and largest i; the first of equals) of every alignment that has
// one, by alignment index.
std::map<std::size_t, std::pair<RetainedPair, RetainedPair>> retained_ends(const PruningResult& pruning);

}  // namespace seqtopo::mapping
