#pragma once
// The map files of `seqtopo map` (INTERFACE.md): map.json, alignments.json and loop_closures.csv, as text.
#include <cstddef>
#include <span>
#include <string>

#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::formats {

// One session of a map made of several (seqtopo map S1 S2 ...): its input and its images [begin, end).
struct MapSession {
  std::string input;
  std::size_t begin = 0, end = 0;
  // A session that begins at a break found inside its input (timeline/session_breaks.hpp): the gap in the frames'
  // times before it and the recording's median interval [s]; 0 for an input's first session.
  double gap = 0, median_interval = 0;
};

// {"images", "labels", "places", "edges", "junctions", "segments", "alignments"} (alignments with "kept"); with
// two sessions or more also "sessions": [{"input", "begin", "end"[, "break": {"gap", "median_interval"}]}, ...]
// and "image_sessions": [session of every image].
std::string map_json(const mapping::MapResult& result, std::span<const MapSession> sessions = {});
// {"alignments": [... with "kept", "path_score", "e_value"], "rejected_by_odometry": [...], "insignificant": [...],
//  "significance": {...}} (INTERFACE.md); `descriptor_names` name a descriptor left out in its notes
// (decision_notes.hpp).
std::string alignments_json(const mapping::MapResult& result, std::span<const std::string> descriptor_names = {});
// i,j,score,e_value for every retained pair after pruning (e_value empty without statistics).
std::string loop_closures_csv(const mapping::MapResult& result);

}  // namespace seqtopo::formats
