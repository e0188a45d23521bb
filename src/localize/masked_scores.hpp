#pragma once
// Frames of little information in localization (LowInformationFrames): one query frame's aligned scores masked, the
// one rule of the offline matrix (soft_mask) and the online localizer's rows (the frames as flags:
// significance::frame_flags).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace seqtopo::localize::detail {

// Every score of the row at most 0 when the query frame is of little information, else those of the map frames
// flagged in `map_masked` (empty: none).
inline void soft_mask_row(float* scores, std::size_t cols, bool query_masked, const std::vector<bool>& map_masked) {
  for (std::size_t j = 0; j < cols; ++j) {
    if (query_masked || (!map_masked.empty() && map_masked[j])) scores[j] = std::min(scores[j], 0.0F);
  }
}

}  // namespace seqtopo::localize::detail
