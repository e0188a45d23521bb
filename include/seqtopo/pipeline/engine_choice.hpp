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

#include "seqtopo/pipeline/map_pipeline.hpp"

namespace seqtopo::pipeline {

enum class MapEngine { exact, fast, streaming, sparse };

struct EngineChoice {
  MapEngine engine = MapEngine::exact;
  std::string why;  // one line: the engine, the estimated peak and the budget
};

// Why `request` cannot run streamed (--streaming), or empty when it can. Only settings the user chose stand in
// the way; the descriptors are adapted by streaming_settings.
std::string streaming_obstacle(const MapRequest& request, InputKind kind);

// The nearest settings that stream: images compared by one vector descriptor (the first of patch or panorama
// among settings.descriptors, patch when neither is there) by cosine similarity; a descriptors.npy by cosine.
// Returns what changed, for the user ("" when nothing did).
std::string streaming_settings(MapSettings& settings, InputKind kind);

// The choice for `images` images of `request` (which must not force an engine) against `budget` bytes; with
// no budget known, exact.
EngineChoice choose_engine(const MapRequest& request, InputKind kind, std::size_t images,
                           std::optional<std::size_t> budget);

// `request` with the choice applied (engine, streaming, and the streaming settings); returns their note.
std::string apply_engine_choice(MapRequest& request, InputKind kind, const EngineChoice& choice);

}  // namespace seqtopo::pipeline
