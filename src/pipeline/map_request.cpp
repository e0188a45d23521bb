#include "seqtopo/pipeline/map_request.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

#include "seqtopo/pipeline/ground_truth.hpp"

namespace seqtopo::pipeline {

namespace {

constexpr std::array<std::pair<MapEngine, std::string_view>, 5> kEngineNames{{{MapEngine::automatic, "automatic"},
                                                                              {MapEngine::exact, "exact"},
                                                                              {MapEngine::fast, "fast"},
                                                                              {MapEngine::streaming, "streaming"},
                                                                              {MapEngine::sparse, "sparse"}}};

}  // namespace

std::string_view engine_name(MapEngine engine) {
  for (const auto& [e, name] : kEngineNames) {
    if (e == engine) return name;
  }
  return "?";
}

MapEngine parse_engine(std::string_view name) {
  for (const auto& [e, known] : kEngineNames) {
    if (known == name) return e;
  }
  throw std::invalid_argument(
      fmt::format("expected automatic, exact, fast, streaming or sparse, got '{}'", std::string(name)));
}

MapEngine engine_with_flags(std::optional<MapEngine> engine, bool streaming, bool sparse) {
  const MapEngine asked = engine.value_or(MapEngine::automatic);
  if (!streaming && !sparse) return asked;
  const MapEngine flag = sparse ? MapEngine::sparse : MapEngine::streaming;
  if (asked == MapEngine::exact || (asked == MapEngine::streaming && sparse)) {
    throw InputError("--engine",
                     fmt::format("{} disagrees with --{}: {}", engine_name(asked), engine_name(flag),
                                 asked == MapEngine::exact ? "exact fills an N x N table, which streaming never holds"
                                                           : "give one of them"));
  }
  return flag;
}

void apply_section_overrides(align::ScoreSettings& score, align::SearchSettings& search,
                             align::SignificanceSettings& significance, const MapOverrides& o) {
  if (o.contrast_window) score.contrast_window = *o.contrast_window;
  if (o.contrast_offset) score.contrast_offset = *o.contrast_offset;
  if (o.gap) search.gap = *o.gap;
  if (o.no_cap) search.cap.reset();
  if (o.cap) search.cap = *o.cap;
  if (o.min_separation) search.min_separation = *o.min_separation;
  if (o.reverse) search.reverse = *o.reverse;
  if (o.no_e_value) significance.max_e_value.reset();
  if (o.e_value) significance.max_e_value = *o.e_value;
  if (o.threshold) significance.threshold = *o.threshold;
}

MapSettings apply_overrides(MapSettings s, const MapOverrides& o) {
  apply_descriptor_overrides(o.described, s.descriptors, s.detect_panoramas, s.similarity);
  if (o.described.threads) s.map.threads = *o.described.threads;
  apply_section_overrides(s.map.score, s.map.search, s.map.significance, o);
  if (o.no_cap || o.cap) s.map.cap_from_statistics = false;  // an explicit cap is the cap
  if (o.cap_factor) s.map.cap_factor = static_cast<float>(*o.cap_factor);
  if (o.frames_per_place) s.map.frames_per_place = *o.frames_per_place;
  if (o.alignment_set) s.map.alignment_set = *o.alignment_set;
  if (o.no_odometry_gate) s.map.odometry.gate.reset();
  if (o.odometry_gate) s.map.odometry.gate = *o.odometry_gate;
  if (o.graph_cleanup) s.map.graph.clean = *o.graph_cleanup;
  if (o.odometry_evidence) s.map.odometry.evidence = *o.odometry_evidence;
  return s;
}

std::optional<InputError> streaming_obstacle(const MapRequest& request, InputKind kind) {
  const MapSettings& s = request.settings;
  const std::string engine_option = request.engine == MapEngine::sparse ? "--sparse" : "--streaming";
  if (request.preset == "paper") {
    return InputError("--preset",
                      "paper aligns the raw S = 1 - kappa D, whose kappa needs the whole distance matrix; "
                      "streaming never holds it (use the default preset)");
  }
  if (kind == InputKind::similarity) {
    return InputError(engine_option,
                      "needs descriptors (descriptors.npy, or images with one vector descriptor), not a similarity "
                      "matrix");
  }
  if (s.map.alignment_set == align::AlignmentSet::locally_optimal) {
    return InputError("--alignment-set", "locally-optimal keeps the N x N scores; streaming never holds them");
  }
  if (s.map.score.contrast_window == 0) {
    return InputError("--contrast-window",
                      "0 aligns the raw S = 1 - kappa D, whose kappa needs the whole distance matrix; streaming "
                      "aligns contrast-enhanced scores (window >= 1)");
  }
  if (s.similarity.kappa) {
    return InputError("--kappa", "has no effect when streaming: the contrast enhancement removes kappa");
  }
  if (s.similarity.distance && *s.similarity.distance != Distance::cosine) {
    return InputError("--metric", fmt::format("streaming scores by cosine similarity only, got '{}'",
                                              similarity::distance_name(*s.similarity.distance)));
  }
  if (!s.detect_panoramas) {  // the descriptors were asked for: they are used as they are
    if (s.descriptors.size() != 1) {
      return InputError("--descriptor", fmt::format("streaming takes one descriptor, got {} (fusing needs one N x N "
                                                    "matrix per descriptor)",
                                                    s.descriptors.size()));
    }
    if (kind != InputKind::descriptors && s.descriptors.front() == Descriptor::npy) {
      return InputError("--descriptor", "npy needs a descriptors.npy input");
    }
    if (kind != InputKind::descriptors && s.descriptors.front() == Descriptor::joint_histogram) {
      return InputError("--descriptor",
                        "joint-histogram is a sparse histogram without a vector form; streaming needs patch or "
                        "panorama (compared by cosine)");
    }
  }
  const auto& truth = request.truth.same_place;
  if (!truth.empty() && is_same_place_matrix_file(truth)) {
    return InputError("--ground-truth",
                      "an N x N image or matrix (N^2 bytes, 10 GB at 10^5 images) is refused when streaming; give "
                      "pairs (query,map CSV), VPR-Bench .npy, or poses with --gt-radius");
  }
  return std::nullopt;
}

void check_request(const MapRequest& request, InputKind kind) {
  if (request.sessions.empty()) throw InputError("input", "no input given");
  if (request.engine != MapEngine::sparse) {
    if (request.sparse.neighbours) throw InputError("--neighbours", "is the sparse engine's: give --sparse too");
    if (request.sparse.diagonal_reach) {
      throw InputError("--diagonal-reach", "is the sparse engine's: give --sparse too");
    }
  }
  if (request.sparse.neighbours && *request.sparse.neighbours == 0) {
    throw InputError("--neighbours", "must be at least 1");
  }
  if (streams(request.engine)) {
    if (auto obstacle = streaming_obstacle(request, kind)) throw *obstacle;
  }
}

}  // namespace seqtopo::pipeline
