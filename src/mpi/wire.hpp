#pragma once
// What seqtopo-mpi's ranks exchange, as plain arrays: the sparse scores, the components dealt to a
// rank, and the alignments it found. No MPI here; main.cpp moves the arrays.
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_components.hpp"

namespace seqtopo::mpi {

// Sparse scores: header {rows, cols, bits of background}, entries per row, then columns and values.
struct ScoresWire {
  std::vector<std::uint64_t> header;
  std::vector<std::uint64_t> row_counts;
  std::vector<std::uint32_t> columns;
  std::vector<float> values;
};
ScoresWire encode_scores(const scale::SparseScores& scores);
scale::SparseScores decode_scores(const ScoresWire& wire);

// Components: every field as one 64-bit word (best as its float bits), then the row offsets of the runs and the
// runs (first column in the high 32 bits, length in the low).
std::vector<std::uint64_t> encode_components(std::span<const scale::SparseComponent* const> components);
std::vector<scale::SparseComponent> decode_components(std::span<const std::uint64_t> words);

// The alignments of each of a rank's components, in the order it received them: the integers
// (counts, direction, ranges, pairs) and the scores (exact float values) apart.
struct AlignmentsWire {
  std::vector<std::uint64_t> words;
  std::vector<float> scores;
};
AlignmentsWire encode_alignments(const std::vector<std::vector<align::LocalAlignment>>& per_component);
std::vector<std::vector<align::LocalAlignment>> decode_alignments(const AlignmentsWire& wire);

}  // namespace seqtopo::mpi
