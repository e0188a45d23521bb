#pragma once
// Frames of little information in a map (MapConfig::mask_low_information): their scores soft-masked, their pairs
// placed between the evidence on either side.
#include <cstddef>
#include <string>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::mapping::detail {

// The sequence the map's alignment sees: every frame but those left out, in order, so a stretch left out is a free
// step from the frame before it to the frame after it. Left out are long stretches of frames of little information
// (long_stretches): a revisit with such a stretch in one pass only (the lights out) is then one alignment, where a
// gap across it would have cost its whole evidence and left two pieces too short to be significant; the same
// stretch in both passes is a step in both. Short stretches stay in place, soft-masked (soft_masked): left out, the
// frames between them would join into a sequence of their own, a run of tunnels' daylight fragments aligned with
// itself at a lag. Their pairs are placed afterwards (through_masked_frames).
class UnmaskedFrames {
 public:
  // Of `frames` frames, those flagged in `left_out` (empty: none) left out.
  UnmaskedFrames(std::size_t frames, const std::vector<bool>& left_out);
  // The frame of unmasked index k.
  std::size_t frame(std::size_t k) const { return frames_[k]; }
  std::size_t size() const { return frames_.size(); }
  bool keeps(std::size_t frame) const { return index_[frame] != static_cast<std::size_t>(-1); }
  // Per frame of the view, its flag in `flags` (one per frame, or empty: returned as it is).
  std::vector<bool> of_view(const std::vector<bool>& flags) const;
  // `full` (frames x frames) read at the frames kept only: itself when none is left out.
  align::ScoreSource view(const align::ScoreSource& full) const;
  // An alignment of view() in the frames' own indices (ranges spanning its pairs), and back: the pairs of frames
  // left out dropped.
  align::LocalAlignment to_frames(align::LocalAlignment alignment) const;
  align::LocalAlignment to_unmasked(const align::LocalAlignment& alignment) const;

 private:
  std::vector<std::size_t> frames_;
  std::vector<std::size_t> index_;  // of each frame, or npos when masked
  bool any_ = false;
};

// The indices of the frames flagged, ascending.
std::vector<std::size_t> flagged_frames(const std::vector<bool>& flags);

// Frames flagged in runs of at least `min_length` consecutive flagged frames (empty when none).
std::vector<bool> long_stretches(const std::vector<bool>& flags, std::size_t min_length);

// `scores` with every cell in a masked row or column at most 0, read a row segment at a time (`masked` empty or
// all false: `scores` itself).
align::ScoreSource soft_masked(const align::ScoreSource& scores, const std::vector<bool>& masked);

// Every cell in a masked row or column at most `ceiling`: the scores as the outputs show them, where such a frame
// carries no evidence of a revisit; the cells below the ceiling keep their value. `masked` empty: nothing.
void soft_mask(SimilarityMatrix& enhanced, const std::vector<bool>& masked, float ceiling);

// The alignments with pairs placed along the straight line between two consecutive pairs of unmasked frames where
// both passes skip frames between them, masked ones in at least one (a tunnel driven through twice, a dark frame in
// one pass: no evidence of where the path runs there, UnmaskedFrames left them out), as many as the shorter
// crossing has frames; pairs of masked frames at either end, with evidence on one side only, cut off. A stretch
// skipped by one pass only (the lights out where the other pass has no frame) gets no pair. Returns
// the indices of the alignments that keep a pair of unmasked frames (an alignment of masked frames alone is none).
std::vector<std::size_t> through_masked_frames(std::vector<align::LocalAlignment>& alignments,
                                               const std::vector<bool>& masked);

// The posteriors (one per pair of `alignment`) of its pairs of masked frames: the smaller of the nearest pairs'
// with evidence before and after, times min(1, (2 tolerance + 1) / (|di - dj| + 1)) where the passes cross the
// stretch in di and dj frames. Pairs outside any such stretch keep theirs.
void posteriors_through_masked(const align::LocalAlignment& alignment, const std::vector<bool>& masked,
                               std::size_t tolerance, std::vector<double>& posteriors);

}  // namespace seqtopo::mapping::detail
