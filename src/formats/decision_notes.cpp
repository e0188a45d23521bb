#include "seqtopo/formats/decision_notes.hpp"

#include <fmt/format.h>

namespace seqtopo::formats {

std::vector<std::pair<std::size_t, std::size_t>> frame_stretches(std::span<const std::size_t> sorted) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (const std::size_t f : sorted) {
    if (runs.empty() || f != runs.back().second + 1) {
      runs.emplace_back(f, f);
    } else {
      runs.back().second = f;
    }
  }
  return runs;
}

std::vector<std::string> decision_notes(const mapping::MapDecisions& d, std::span<const std::string> names) {
  std::vector<std::string> notes;
  if (d.place_scale_missing) {
    notes.emplace_back(
        "no place scale: the similarity keeps falling with the lag (a drifting sequence) or the sequence is short; "
        "windows and separations count frames");
  }
  for (const std::size_t k : d.blind_descriptors) {
    notes.push_back(fmt::format(
        "descriptor {} of {}{} sees no revisit (none on its own, nor higher scores than chance on the pairs another "
        "maps): left out of the fusion",
        k + 1, d.similarities, k < names.size() ? fmt::format(" ({})", names[k]) : std::string()));
  }
  if (!d.low_information_frames.empty()) {
    const auto& f = d.low_information_frames;  // sorted
    const std::size_t stretches = frame_stretches(f).size();
    notes.push_back(fmt::format(
        "{} frame{} of little information (dark or near-uniform{}) in {} stretch{}: no evidence of a "
        "revisit (left out of the alignment), their loop closures only where a revisit runs through them",
        f.size(), f.size() == 1 ? "" : "s",
        d.tandem_repeat_frames == 0 ? std::string()
                                    : fmt::format("; {} of them in tandem repeats, below", d.tandem_repeat_frames),
        stretches, stretches == 1 ? "" : "es"));
  }
  for (const auto& p : d.linear_phase) {
    if (p.raised_to) {
      notes.push_back(p.by_global_rate
                          ? fmt::format("contrast offset {:.2f}: the scores' global alignment rate is {:.3f} a step, "
                                        "above {:.2f} (linear phase); raised to {:.2f}",
                                        p.offset, p.global_rate, p.bound, *p.raised_to)
                          : fmt::format("contrast offset {:.2f}: chance alignments grow with the sequence ({:.1f} "
                                        "places, linear phase); raised to {:.2f}",
                                        p.offset, p.chance_length, *p.raised_to));
    } else {
      notes.push_back(p.by_global_rate
                          ? fmt::format("the scores' global alignment rate stays at {:.3f} a step even at contrast "
                                        "offset {:.2f}: revisits may be overestimated",
                                        p.global_rate, p.offset)
                          : fmt::format("chance alignments stay long ({:.1f} places) even at contrast offset {:.2f}: "
                                        "revisits may be overestimated",
                                        p.chance_length, p.offset));
    }
  }
  if (d.unfitted_chance_alignments) {
    notes.push_back(fmt::format(
        "too few chance alignments ({}) to fit the significance statistics: a fixed threshold of {:.4g} and cap {} "
        "apply",
        *d.unfitted_chance_alignments, d.score_threshold, d.cap ? fmt::format("{:.4g}", *d.cap) : "none"));
  }
  if (d.trimmed_chance_end_pairs > 0) {
    notes.push_back(fmt::format("{} aligned pairs at alignments' ends more likely chance than revisit trimmed off",
                                d.trimmed_chance_end_pairs));
  }
  if (d.trimmed_odometry_pairs > 0) {
    notes.push_back(fmt::format("odometry: {} aligned pairs past the places where two paths part trimmed off",
                                d.trimmed_odometry_pairs));
  }
  if (d.tandem_repeat_frames > 0) {
    notes.push_back(
        fmt::format("{} frames in tandem repeats of appearance (they resemble frames one and two periods away within "
                    "the self-alignment band: identical doors, shelves) carry no evidence of a revisit",
                    d.tandem_repeat_frames));
  }
  return notes;
}

}  // namespace seqtopo::formats
