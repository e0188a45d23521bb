#pragma once
// Which engine a `seqtopo map` run uses when none is asked for: the one whose run fits the machine, from the
// estimate of memory_estimate.hpp, cheapest in accuracy first:
//   exact      the scalar reference with its N x N table, while the run's peak is within a quarter of the budget;
//   fast       the vectorized engine (no N x N table; scores quantized to 1/512, the same maps on every
//              measured input, docs/engine.md), while that peak is within a quarter;
//   streaming  never the N x N matrix: contrast-enhanced cosine scores of one vector descriptor computed when
//              the engine reads them, while its peak is within half the budget and the settings can stream;
//   sparse     only each frame's nearest neighbours aligned (--sparse), while its peak is within half the budget;
//   otherwise fast again, and the memory check refuses the run naming what would fit.
// The budget is similarity::memory_budget_bytes() (the machine's memory, its cgroup limit, SEQTOPO_MEMORY_LIMIT),
// not what happens to be free, so the choice, and with it the map, is the same on every run on one machine.
#include <cstddef>
#include <optional>
#include <string>

#include "seqtopo/pipeline/map_request.hpp"

namespace seqtopo::pipeline {

struct EngineChoice {
  MapEngine engine = MapEngine::exact;
  std::string why;  // one line: the engine, the estimated peak and the budget
};

// The nearest settings that stream: images compared by one vector descriptor (the first of patch or panorama
// among settings.descriptors, patch when neither is there) by cosine similarity; a descriptors.npy by cosine.
// Returns what changed, for the user ("" when nothing did).
std::string streaming_settings(MapSettings& settings, InputKind kind);

// The choice for `images` images of `request` (whose own engine is not read) against `budget` bytes; with no
// budget known, exact.
EngineChoice choose_engine(const MapRequest& request, InputKind kind, std::size_t images,
                           std::optional<std::size_t> budget);

// `request` set to run `engine` (not automatic): request.engine, the mapping engine of its settings, and for the
// streaming engines the streaming settings. Returns what changed in the settings ("" when nothing did).
std::string apply_engine(MapRequest& request, InputKind kind, MapEngine engine);

// The one translation of request.engine: automatic is chosen for `images` images (when known; exact otherwise)
// against `budget`, then applied. Returns the note for the user: the choice and why, and what the streaming
// settings changed ("" when the engine was asked for and nothing changed).
std::string resolve_engine(MapRequest& request, InputKind kind, std::optional<std::size_t> images,
                           std::optional<std::size_t> budget);

}  // namespace seqtopo::pipeline
