#pragma once
// Frames inside a tandem repeat of appearance: a corridor of identical doors, a row of identical shelves, a colonnade.
// Such a stretch matches itself shifted by one period, by two, ..., and each shift is an alignment far beyond chance
// (a 120-frame stretch of a 6-frame door pattern in an otherwise unrevisited walk: alignments at E 1e-10 to 1e-22 in
// every seed) that says nothing about a revisit, as a tandem repeat in DNA scores highly against itself at every
// multiple of its period. Sequence search masks such regions before it scores (Benson's Tandem Repeats Finder, 1999;
// DUST, Morgulis et al. 2006); the map soft-masks these frames with the dark ones (mapping::MapConfig::
// mask_low_information): they carry no evidence of a revisit, an alignment still runs through them.
//
// A frame is in a tandem repeat when the diagonals of the scores around it (the mean enhanced score of the pairs
// (k, k + d), or of (k - d, k), for the frames k within `half_window` of it: averaged, the noise of one cell falls by
// the square root of their number) stand above `level` one period and two periods away (runs of diagonals centred at p
// and 2p, within a frame and a half), not counting a run next to the `near` diagonals (the sequence's own smoothness,
// or a stop, continued). A U-turn is an anti-diagonal, not a diagonal; a revisit comes from farther than `reach`. The
// frames between two such frames at most `reach` apart are in the repeat too (its frames each show the period only
// where the noise lets them); stretches of fewer than `min_frames` frames are left alone: a coincidence of a few frames
// is not a repeat. The map reads twice its self-alignment band (min_separation), so periods up to the band are found
// (longer ones are revisits the band lets through), and takes the band as `min_frames` (a shorter repeat cannot align
// with itself beyond the band).
#include <cstddef>
#include <vector>

#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::significance {

struct TandemRepeatConfig {
  std::size_t near = 2;         // [frames] diagonals left out (a smooth sequence resembles its neighbours)
  std::size_t reach = 30;       // [frames] the farthest diagonal read
  std::size_t half_window = 5;  // [frames] the frames either side a diagonal is averaged over
  double level = 0.75;          // [standard deviations] mean enhanced score of a diagonal that counts as alike
  std::size_t min_frames = 30;  // a shorter stretch is not a repeat
};

// The frames (sorted indices) in a tandem repeat of the square, symmetric enhanced scores (contrast-enhanced, no
// offset: mapping::enhanced_scores). Throws std::invalid_argument for a non-square matrix, near >= reach or a level
// that is not a positive number.
std::vector<std::size_t> tandem_repeat_frames(const SimilarityMatrix& enhanced, const TandemRepeatConfig& config = {});
// The same read from any source (a streamed similarity: only the band of `reach` diagonals above the main one is
// read, each row segment once, and at most reach + 2 half_window + 1 of them are held).
std::vector<std::size_t> tandem_repeat_frames(const align::ScoreSource& enhanced,
                                              const TandemRepeatConfig& config = {});

}  // namespace seqtopo::significance
