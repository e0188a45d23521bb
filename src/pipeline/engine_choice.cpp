#include "seqtopo/pipeline/engine_choice.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/similarity/memory.hpp"

namespace seqtopo::pipeline {

std::string streaming_obstacle(const MapRequest& request, InputKind kind) {
  const MapSettings& s = request.settings;
  if (request.preset == "paper") return "the paper preset aligns the raw S = 1 - kappa D, whose kappa needs N x N";
  if (kind == InputKind::similarity) return "the input is a similarity matrix";
  if (s.map.alignment_set == align::AlignmentSet::locally_optimal) return "locally-optimal keeps the N x N scores";
  if (s.map.contrast_window == 0) return "a contrast window of 0 aligns the raw S, whose kappa needs N x N";
  if (s.similarity.kappa) return "--kappa needs the N x N distances";
  if (s.similarity.distance && *s.similarity.distance != Distance::cosine) return "streaming compares by cosine only";
  const auto& truth = request.truth.same_place;
  if (!truth.empty() && std::filesystem::path(truth).extension() != ".csv") {
    return "an N x N ground-truth image is refused when streaming";
  }
  return {};
}

std::string streaming_settings(MapSettings& settings, InputKind kind) {
  const bool was_cosine = settings.similarity.distance == Distance::cosine;
  settings.similarity.distance = Distance::cosine;
  if (kind == InputKind::descriptors) return was_cosine ? "" : "descriptors.npy rows compared by cosine";
  Descriptor vector = Descriptor::patch;
  for (Descriptor d : settings.descriptors) {
    if (d == Descriptor::patch || d == Descriptor::panorama) {
      vector = d;
      break;
    }
  }
  const bool same = settings.descriptors.size() == 1 && settings.descriptors.front() == vector && was_cosine;
  settings.descriptors = {vector};
  return same ? ""
              : fmt::format("images compared by the {} descriptor's cosine (one vector descriptor streams)",
                            descriptor_name(vector));
}

namespace {

std::size_t peak_of(MapRequest request, InputKind kind, std::size_t images, MapEngine engine) {
  request.settings.map.engine =
      engine == MapEngine::exact ? mapping::MapConfig::Engine::exact : mapping::MapConfig::Engine::fast;
  request.streaming = engine == MapEngine::streaming || engine == MapEngine::sparse;
  request.sparse = engine == MapEngine::sparse;
  if (request.streaming) streaming_settings(request.settings, kind);
  return estimate_map_memory(map_memory_input(request, kind, images)).peak;
}

}  // namespace

EngineChoice choose_engine(const MapRequest& request, InputKind kind, std::size_t images,
                           std::optional<std::size_t> budget) {
  if (!budget) return {MapEngine::exact, "engine exact (the machine's memory is unknown)"};
  const std::string total = similarity::format_bytes(*budget);
  const std::size_t exact = peak_of(request, kind, images, MapEngine::exact);
  if (exact <= *budget / 4) {
    return {MapEngine::exact, fmt::format("engine exact: its N x N table fits (the run needs about {}, a quarter "
                                          "of {} is the limit)",
                                          similarity::format_bytes(exact), total)};
  }
  const std::size_t fast = peak_of(request, kind, images, MapEngine::fast);
  if (fast <= *budget / 4) {
    return {MapEngine::fast, fmt::format("engine fast: the exact engine's N x N table would take the run to {}, "
                                         "more than a quarter of {}; the fast engine needs about {}",
                                         similarity::format_bytes(exact), total, similarity::format_bytes(fast))};
  }
  const std::string obstacle = streaming_obstacle(request, kind);
  if (obstacle.empty()) {
    const std::size_t streamed = peak_of(request, kind, images, MapEngine::streaming);
    if (streamed <= *budget / 2) {
      return {MapEngine::streaming,
              fmt::format("engine streaming: the N x N matrices would take the run to {} (fast engine), more than "
                          "a quarter of {}; streamed it needs about {}",
                          similarity::format_bytes(fast), total, similarity::format_bytes(streamed))};
    }
    const std::size_t sparse = peak_of(request, kind, images, MapEngine::sparse);
    if (sparse <= *budget / 2) {
      return {MapEngine::sparse,
              fmt::format("engine sparse: streamed every pair the run would need {}, more than half of {}; aligning "
                          "each frame's {} nearest neighbours it needs about {} (a revisit under strong appearance "
                          "change, whose frames' nearest neighbours are seldom right, needs --diagonal-reach)",
                          similarity::format_bytes(streamed), total, request.sparse_neighbours,
                          similarity::format_bytes(sparse))};
    }
  }
  return {MapEngine::fast,
          fmt::format("engine fast: the run needs about {}{}", similarity::format_bytes(fast),
                      obstacle.empty() ? std::string() : fmt::format(" (it cannot stream: {})", obstacle))};
}

std::string apply_engine_choice(MapRequest& request, InputKind kind, const EngineChoice& choice) {
  request.settings.map.engine =
      choice.engine == MapEngine::exact ? mapping::MapConfig::Engine::exact : mapping::MapConfig::Engine::fast;
  request.streaming = choice.engine == MapEngine::streaming || choice.engine == MapEngine::sparse;
  request.sparse = choice.engine == MapEngine::sparse;
  if (!request.streaming) return choice.why;
  const std::string changed = streaming_settings(request.settings, kind);
  return changed.empty() ? choice.why : choice.why + "; " + changed;
}

}  // namespace seqtopo::pipeline
