#pragma once
// The map files of `seqtopo map` (INTERFACE.md): map.json, alignments.json and loop_closures.csv, as text.
#include <string>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::formats {

// {"images", "labels", "places", "edges", "junctions", "segments", "alignments"} (alignments with "kept").
std::string map_json(const mapping::MapResult& result);
// {"alignments": [... with "kept"], "rejected_by_odometry": [...]}
std::string alignments_json(const mapping::MapResult& result);
// i,j,score for every retained pair after pruning.
std::string loop_closures_csv(const mapping::PruningResult& pruning);

}  // namespace seqtopo::formats
