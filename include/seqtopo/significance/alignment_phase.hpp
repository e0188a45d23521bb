#pragma once
// Whether gapped local alignment of a sequence's scores is in the logarithmic phase, from the scores alone.
//
// Arratia & Waterman (1994, "A phase transition for the score in matching random sequences allowing
// deletions"): for i.i.d. cell scores and a gap penalty, the best local alignment of two random sequences of
// length n grows like log n when the best *global* alignment's score per step, lim G(n, n) / n, is negative,
// and like n when it is positive. Near zero the logarithmic phase holds in name only: its chance alignments are
// long, as in the linear phase. The rate has no closed form for gapped alignment; it is estimated here by
// aligning globally an n x n table of cells drawn from the sequence's own scores (which removes their
// correlation along the diagonals: a smooth sequence is measured in places elsewhere).
#include <cstddef>
#include <cstdint>
#include <span>

namespace seqtopo::significance {

// G(n, n) / n for the global alignment of the n x n table `cells` (row-major): G(0, 0) = 0, G(i, 0) = -i gap,
// G(0, j) = -j gap, G(i, j) = max(G(i-1, j-1) + cell(i-1, j-1), G(i-1, j) - gap, G(i, j-1) - gap).
double global_alignment_rate(std::span<const float> cells, std::size_t n, float gap);

// The phase check's sample, the same offline and online: a kPhaseTable x kPhaseTable table drawn from up to
// kPhaseCells of the sequence's scores.
inline constexpr std::size_t kPhaseTable = 256, kPhaseCells = 65536;

// The same for an n x n table drawn with replacement from `scores` (deterministic for a seed). Throws
// std::invalid_argument when `scores` is empty or n is 0.
double resampled_global_rate(std::span<const float> scores, std::size_t n, float gap, std::uint64_t seed = 1);

}  // namespace seqtopo::significance
