#include "seqtopo/align/settings.hpp"

#include <algorithm>
#include <cmath>

namespace seqtopo::align {

std::size_t places_in_frames(double places, double frames_per_place) {
  // Saturated: a count beyond 2^62 frames is beyond any sequence (and its conversion would be undefined).
  const double frames = std::max(1.0, std::round(places * frames_per_place));
  return frames < 0x1p62 ? static_cast<std::size_t>(frames) : std::size_t{1} << 62U;
}

ScoreSettings in_frames(const ScoreSettings& score, Unit unit, double frames_per_place) {
  ScoreSettings f = score;
  if (unit == Unit::places && score.contrast_window > 0)
    f.contrast_window = places_in_frames(static_cast<double>(score.contrast_window), frames_per_place);
  return f;
}

SearchSettings in_frames(const SearchSettings& search, Unit unit, double frames_per_place) {
  SearchSettings f = search;
  if (unit == Unit::places)
    f.min_separation = places_in_frames(static_cast<double>(search.min_separation), frames_per_place);
  return f;
}

}  // namespace seqtopo::align
