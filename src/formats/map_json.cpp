#include "seqtopo/formats/map_json.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "seqtopo/formats/alignment_json.hpp"

namespace seqtopo::formats {

std::string map_json(const mapping::MapResult& result, std::span<const MapSession> sessions) {
  const auto& map = result.map;
  nlohmann::json places = nlohmann::json::array();
  for (const auto& p : map.places) places.push_back({{"id", p.id}, {"images", p.images}});
  nlohmann::json edges = nlohmann::json::array();
  for (auto [p, q] : map.edges) edges.push_back({p, q});
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& s : map.segments) segments.push_back(s.places);
  nlohmann::json document = {{"images", map.labels.size()},
                             {"labels", map.labels},
                             {"places", places},
                             {"edges", edges},
                             {"junctions", map.junctions},
                             {"segments", segments},
                             {"alignments", alignments_to_json(result.alignments, &result.pruning.kept)["alignments"]}};
  if (sessions.size() > 1) {
    nlohmann::json list = nlohmann::json::array();
    std::vector<std::size_t> of_image(map.labels.size(), 0);
    for (std::size_t k = 0; k < sessions.size(); ++k) {
      const auto& s = sessions[k];
      list.push_back({{"input", s.input}, {"begin", s.begin}, {"end", s.end}});
      for (std::size_t i = s.begin; i < s.end && i < of_image.size(); ++i) of_image[i] = k;
    }
    document["sessions"] = list;
    document["image_sessions"] = of_image;
  }
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
