#include "seqtopo/formats/map_json.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "seqtopo/formats/alignment_json.hpp"

namespace seqtopo::formats {

std::string map_json(const mapping::MapResult& result) {
  const auto& map = result.map;
  nlohmann::json places = nlohmann::json::array();
  for (const auto& p : map.places) places.push_back({{"id", p.id}, {"images", p.images}});
  nlohmann::json edges = nlohmann::json::array();
  for (auto [p, q] : map.edges) edges.push_back({p, q});
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& s : map.segments) segments.push_back(s.places);
  const nlohmann::json document = {
      {"images", map.labels.size()},
      {"labels", map.labels},
      {"places", places},
      {"edges", edges},
      {"junctions", map.junctions},
      {"segments", segments},
      {"alignments", alignments_to_json(result.alignments, &result.pruning.kept)["alignments"]}};
  return document.dump(1) + "\n";
}

std::string alignments_json(const mapping::MapResult& result) {
  return nlohmann::json{{"alignments", alignments_to_json(result.alignments, &result.pruning.kept)["alignments"]},
                        {"rejected_by_odometry", alignments_to_json(result.rejected)["alignments"]}}
             .dump(1) +
         "\n";
}

std::string loop_closures_csv(const mapping::PruningResult& pruning) {
  std::string csv = "i,j,score\n";
  for (const auto& p : pruning.pairs) csv += fmt::format("{},{},{}\n", p.i, p.j, p.score);
  return csv;
}

}  // namespace seqtopo::formats
