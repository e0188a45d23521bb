#include "seqtopo/formats/map_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "seqtopo/formats/alignment_json.hpp"
#include "seqtopo/formats/decision_notes.hpp"

namespace seqtopo::formats {
namespace {

// JSON has no NaN: a missing E-value (no statistics) is null.
nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// The alignments with their pruning verdict, uncapped path score and E-value.
nlohmann::json alignment_list(const mapping::MapResult& result) {
  nlohmann::json list = alignments_to_json(result.alignments, &result.pruning.kept)["alignments"];
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (k < result.path_scores.size()) list[k]["path_score"] = result.path_scores[k];
    if (k < result.e_values.size()) list[k]["e_value"] = number_or_null(result.e_values[k]);
    if (k < result.posteriors.size() && !result.posteriors[k].empty()) list[k]["posteriors"] = result.posteriors[k];
  }
  return list;
}

nlohmann::json significance_json(const mapping::MapResult& result, std::span<const std::string> descriptor_names) {
  const auto& d = result.decisions;
  nlohmann::json j = {{"frames_per_place", d.frames_per_place},
                      {"frames_per_place_estimated", d.frames_per_place_estimated},
                      {"contrast_window", d.contrast_window},
                      {"min_separation", d.min_separation},
                      {"min_revisit_pairs", d.min_revisit_pairs},
                      {"contrast_offset", d.contrast_offset},
                      {"cap", d.cap ? nlohmann::json(*d.cap) : nlohmann::json(nullptr)},
                      {"score_threshold", d.score_threshold},
                      {"notes", decision_notes(d, descriptor_names)}};
  if (!d.blind_descriptors.empty()) j["blind_descriptors"] = d.blind_descriptors;
  if (!d.low_information_frames.empty()) j["low_information_frames"] = d.low_information_frames;
  if (d.statistics.valid()) {
    j["lambda"] = d.statistics.lambda;
    j["k"] = d.statistics.k;
    j["search_area"] = d.statistics.area;
    j["fitted_alignments"] = d.statistics.fitted;
    j["chance_alignment_places"] = d.chance_length;
    j["odometry_chance_agreement"] = d.odometry_chance_agreement;
  }
  return j;
}

}  // namespace

std::string map_json(const mapping::MapResult& result, std::span<const MapSession> sessions) {
  const auto& map = result.map;
  nlohmann::json places = nlohmann::json::array();
  for (const auto& p : map.places) places.push_back({{"id", p.id}, {"images", p.images}});
  nlohmann::json edges = nlohmann::json::array();
  for (auto [p, q] : map.edges) edges.push_back({p, q});
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& s : map.segments) segments.push_back(s.places);
  nlohmann::json evidence = nlohmann::json::array();
  for (const auto& j : map.junction_evidence) {
    nlohmann::json passes = nlohmann::json::array();
    const auto place_or_null = [](mapping::PlaceLabel p) {
      return p < 0 ? nlohmann::json(nullptr) : nlohmann::json(p);
    };
    for (const auto& pass : j.passes) {
      passes.push_back({{"images", {pass.first_image, pass.last_image + 1}},
                        {"from", place_or_null(pass.from)},
                        {"to", place_or_null(pass.to)},
                        {"session", pass.session}});
    }
    nlohmann::json reasons = nlohmann::json::array();
    if (j.by_degree) reasons.push_back("degree");
    if (j.by_alignment) reasons.push_back("alignment_boundary");
    evidence.push_back({{"place", j.place},
                        {"region", j.region},
                        {"branches", j.branches},
                        {"images", j.images},
                        {"alignments", j.alignments},
                        {"sessions", j.sessions},
                        {"passes", passes},
                        {"reasons", reasons},
                        {"confidence", j.confidence}});
  }
  nlohmann::json document = {{"images", map.labels.size()},
                             {"labels", map.labels},
                             {"places", places},
                             {"edges", edges},
                             {"junctions", map.junctions},
                             {"junction_evidence", evidence},
                             {"segments", segments},
                             {"alignments", alignment_list(result)}};
  if (sessions.size() > 1) {
    nlohmann::json list = nlohmann::json::array();
    std::vector<std::size_t> of_image(map.labels.size(), 0);
    for (std::size_t k = 0; k < sessions.size(); ++k) {
      const auto& s = sessions[k];
      list.push_back({{"input", s.input}, {"begin", s.begin}, {"end", s.end}});
      if (s.gap > 0) list.back()["break"] = {{"gap", s.gap}, {"median_interval", s.median_interval}};
      for (std::size_t i = s.begin; i < s.end && i < of_image.size(); ++i) of_image[i] = k;
    }
    document["sessions"] = list;
    document["image_sessions"] = of_image;
  }
  return document.dump(1) + "\n";
}

std::string alignments_json(const mapping::MapResult& result, std::span<const std::string> descriptor_names) {
  nlohmann::json insignificant = alignments_to_json(result.insignificant)["alignments"];
  for (std::size_t k = 0; k < insignificant.size() && k < result.insignificant_e_values.size(); ++k) {
    insignificant[k]["e_value"] = number_or_null(result.insignificant_e_values[k]);
  }
  nlohmann::json rejected = alignments_to_json(result.rejected)["alignments"];
  for (std::size_t k = 0; k < rejected.size() && k < result.rejected_verdicts.size(); ++k) {
    rejected[k]["reason"] = std::string(mapping::verdict_name(result.rejected_verdicts[k]));
  }
  return nlohmann::json{{"alignments", alignment_list(result)},
                        {"rejected_by_odometry", std::move(rejected)},
                        {"insignificant", std::move(insignificant)},
                        {"significance", significance_json(result, descriptor_names)}}
             .dump(1) +
         "\n";
}

std::string loop_closures_csv(const mapping::MapResult& result) {
  std::string csv = "i,j,score,e_value,confidence\n";
  for (const auto& p : result.pruning.pairs) {
    const double e = p.alignment < result.e_values.size() ? result.e_values[p.alignment] : std::nan("");
    csv += std::isfinite(e) ? fmt::format("{},{},{},{:.4g},{:.6g}\n", p.i, p.j, p.score, e, p.confidence)
                            : fmt::format("{},{},{},,{:.6g}\n", p.i, p.j, p.score, p.confidence);
  }
  return csv;
}

}  // namespace seqtopo::formats
