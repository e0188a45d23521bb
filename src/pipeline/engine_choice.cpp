#include "seqtopo/pipeline/engine_choice.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/similarity/memory.hpp"

namespace seqtopo::pipeline {

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
  apply_engine(request, kind, engine);
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
  const auto obstacle = streaming_obstacle(request, kind);
  if (!obstacle) {
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
                          similarity::format_bytes(streamed), total,
                          request.sparse.neighbours.value_or(SparseOptions::kDefaultNeighbours),
                          similarity::format_bytes(sparse))};
    }
  }
  return {MapEngine::fast,
          fmt::format("engine fast: the run needs about {}{}", similarity::format_bytes(fast),
                      !obstacle ? std::string() : fmt::format(" (it cannot stream: {})", obstacle->what()))};
}

std::string apply_engine(MapRequest& request, InputKind kind, MapEngine engine) {
  request.engine = engine;
  request.settings.map.engine =
      engine == MapEngine::exact ? mapping::MapConfig::Engine::exact : mapping::MapConfig::Engine::fast;
  return streams(engine) ? streaming_settings(request.settings, kind) : std::string();
}

std::string resolve_engine(MapRequest& request, InputKind kind, std::optional<std::size_t> images,
                           std::optional<std::size_t> budget) {
  if (request.engine != MapEngine::automatic) return apply_engine(request, kind, request.engine);
  const EngineChoice choice =
      images ? choose_engine(request, kind, *images, budget)
             : EngineChoice{MapEngine::exact, "engine exact (the number of images is not known before they are read)"};
  const std::string changed = apply_engine(request, kind, choice.engine);
  return changed.empty() ? choice.why : choice.why + "; " + changed;
}

}  // namespace seqtopo::pipeline
