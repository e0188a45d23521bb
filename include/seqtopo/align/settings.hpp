#pragma once
// The named sections of settings that the offline map (mapping::MapConfig), the online map
// (mapping::OnlineMapConfig) and localization (localize::LocalizeConfig) share: how similarities become the
// scores an alignment sums (ScoreSettings, PhaseSettings), how the alignments are searched (SearchSettings) and
// when one counts as real (SignificanceSettings). Each config holds the sections it uses, with its own defaults,
// and the settings only it has beside them. Windows and separations are counted in the config's Unit.
#include <cstddef>
#include <optional>

namespace seqtopo::align {

// What windows and separations count: frames, or places (each spanning the config's frames_per_place frames).
enum class Unit { frames, places };

// Local contrast enhancement of the similarities before alignment (similarity/contrast_enhancement.hpp): the
// aligned score of a pair is its z-score in the neighbourhood of +-contrast_window minus contrast_offset.
struct ScoreSettings {
  std::size_t contrast_window = 10;  // [unit]; 0: the map aligns S itself (localization: the whole row)
  float contrast_offset = 0.5F;      // [standard deviations]
};

// The logarithmic phase of local alignment scores (Arratia & Waterman 1994; significance/alignment_phase.hpp):
// the contrast offset is raised by contrast_offset_step, up to max_contrast_offset, while chance alignments of
// the sequence's own scores grow with it, where no threshold keeps them out.
struct PhaseSettings {
  bool adapt_offset = true;
  float contrast_offset_step = 0.25F;
  float max_contrast_offset = 3.0F;
  // The scores' global alignment rate above this [score units a step] is the linear phase (unset: not checked).
  std::optional<float> max_global_rate = -0.1F;
};

// The capped Smith-Waterman search (the mapping paper, IV-B; align/smith_waterman.hpp).
struct SearchSettings {
  float gap = 1.5F;                  // penalty per skipped image, both sequences [score units]
  std::optional<float> cap = 40.0F;  // on the cumulative score; unset: classical Smith-Waterman
  bool reverse = true;               // also search the paths driven in the opposite direction
  // Self searches (a sequence against itself): pairs closer than this in time never count [unit]. Localization
  // aligns two sequences and needs 0.
  std::size_t min_separation = 10;
};

// When an alignment is real: its E-value, the number of alignments this good expected by chance in this search
// (significance/score_statistics.hpp), at most max_e_value; unset, or before the statistics can be fitted: its
// score at least threshold.
struct SignificanceSettings {
  std::optional<double> max_e_value = 0.01;
  float threshold = 20.0F;  // [score units]
};

// A count of places in frames: rounded, at least 1 (a count beyond 2^62 frames saturates there).
std::size_t places_in_frames(double places, double frames_per_place);
// The sections with their windows and separations counted in frames (as given in Unit::frames; a contrast window
// of 0 stays 0).
ScoreSettings in_frames(const ScoreSettings& score, Unit unit, double frames_per_place);
SearchSettings in_frames(const SearchSettings& search, Unit unit, double frames_per_place);

}  // namespace seqtopo::align
