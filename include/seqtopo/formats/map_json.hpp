#pragma once
// The map files of `seqtopo map` (INTERFACE.md): map.json, alignments.json and loop_closures.csv, as text.
#include <string>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::formats {

// {"images", "labels", "places", "edges", "junctions", "segments", "alignments"} (alignments with "kept").
std::string map_json(const mapping::MapResult& result);
// {"alignments": [... with "kept", "path_score", "e_value"], "rejected_by_odometry": [...], "insignificant": [...],
//  "significance": {...}} (INTERFACE.md)
std::string alignments_json(const mapping::MapResult& result);
// i,j,score,e_value for every retained pair after pruning (e_value empty without statistics).
std::string loop_closures_csv(const mapping::MapResult& result);

}  // namespace seqtopo::formats
