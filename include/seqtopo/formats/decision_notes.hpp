#pragma once
// What a map run adapted and why (mapping::MapDecisions), in words: one line each, in the order the run decided
// them. The lines of alignments.json's "notes", the report and the command's stderr.
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::formats {

// `descriptor_names`: the names of the map's similarities, for a descriptor left out (empty: by number).
std::vector<std::string> decision_notes(const mapping::MapDecisions& decisions,
                                        std::span<const std::string> descriptor_names = {});

// The runs of consecutive frames in sorted frame indices, as [first, last] each, in order: the stretches of masked
// frames as a person reads them.
std::vector<std::pair<std::size_t, std::size_t>> frame_stretches(std::span<const std::size_t> sorted);

}  // namespace seqtopo::formats
