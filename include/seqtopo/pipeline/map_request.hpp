#pragma once
// What a `seqtopo map` run is asked to do, in the one shape the command line, Python and C++ callers fill:
// the sessions, the preset's settings with the user's changes applied (apply_overrides), the engine, the
// ground-truth files. check_request() holds every refusal a request can earn before any work; the job
// (map_pipeline.hpp) resolves the engine (engine_choice.hpp) and runs it.
//
//   pipeline::MapRequest request;
//   request.sessions = {pipeline::SessionSource{{"data/rtabmap-corridor"}}};
//   request.settings = pipeline::apply_overrides(pipeline::map_preset("default"), {.gap = 0.5F});
//   request.engine = pipeline::MapEngine::streaming;
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/presets.hpp"
#include "seqtopo/pipeline/session_input.hpp"

namespace seqtopo::pipeline {

// How the alignments are computed (docs/engine.md, docs/scaling.md):
//   automatic  chosen by the memory the run needs (engine_choice.hpp), said on stderr;
//   exact      the scalar reference with its N x N table;
//   fast       the vectorized engine (no N x N table; scores quantized to 1/512);
//   streaming  never the N x N matrix: contrast-enhanced cosine scores of one vector descriptor computed when the
//              fast engine reads them;
//   sparse     as streaming, but only each frame's nearest neighbours (FAISS candidates) are aligned.
enum class MapEngine { automatic, exact, fast, streaming, sparse };
std::string_view engine_name(MapEngine engine);
// "automatic", "exact", "fast", "streaming" or "sparse"; throws std::invalid_argument naming them otherwise.
MapEngine parse_engine(std::string_view name);
// The engine of `engine` (unset: automatic) with the flags --streaming and --sparse, the names of two of its values
// (Python's `streaming=` and `sparse=`): a flag wins over automatic and fast (the streaming engines align with the
// fast one); exact, or streaming with --sparse, is refused (InputError naming --engine).
MapEngine engine_with_flags(std::optional<MapEngine> engine, bool streaming, bool sparse);
// The engines that never hold the N x N matrix.
inline bool streams(MapEngine engine) { return engine == MapEngine::streaming || engine == MapEngine::sparse; }

// The sparse engine's candidates (scale::CandidateConfig); unset: the defaults below. Set with another engine
// than sparse they are refused (check_request).
struct SparseOptions {
  static constexpr std::size_t kDefaultNeighbours = 10;
  std::optional<std::size_t> neighbours;  // nearest neighbours per frame, >= 1
  // The diagonal and anti-diagonal this many frames around every candidate pair are candidates too
  // (scale::CandidateConfig::diagonal_reach): a revisit under strong appearance change, whose frames' true
  // matches are seldom among their nearest neighbours, grows from a few seeds. Default 0.
  std::optional<std::size_t> diagonal_reach;
  float background = -1.0F;  // the score of every pair that is not a candidate
};

// The ground truth a map is scored against, as the files users give (ground_truth.hpp reads them).
struct MapTruthFiles {
  std::filesystem::path same_place;  // any format of ground_truth.hpp but same-index (poses with `radius`)
  std::optional<double> radius;      // [m]
  std::filesystem::path places;      // places.csv (junctions.csv beside it)
  std::filesystem::path poses;       // poses.csv
};

struct MapRequest {
  // One per input; several are mapped as one sequence, session after session, with no transition between one
  // session's last image and the next one's first.
  std::vector<SessionSource> sessions;
  std::string preset = "default";  // the name `settings` started from (the report; the paper preset never streams)
  MapSettings settings = map_preset("default");
  MapEngine engine = MapEngine::automatic;
  SparseOptions sparse;
  MapTruthFiles truth;
  // The images of a descriptors.npy or similarity.npy input, one per row (thinned by the input's --every alike),
  // shown by the report; empty: the report has no images for them.
  std::filesystem::path report_images;
};

// The user's changes to a preset's settings, by the names of `seqtopo map`'s options; unset: the preset's. One
// function applies them for the command line and Python.
// Default member initializers: `{.gap = 0.5F}` alone stays free of -Wmissing-field-initializers.
struct MapOverrides {
  DescriptorOverrides described = {};  // its threads are the alignment's too
  std::optional<float> gap = {};
  std::optional<float> threshold = {};
  std::optional<float> contrast_offset = {};
  bool no_cap = false;  // --cap none
  std::optional<float> cap = {};
  std::optional<double> cap_factor = {};
  bool no_e_value = false;  // --e-value none
  std::optional<double> e_value = {};
  std::optional<double> frames_per_place = {};
  std::optional<align::AlignmentSet> alignment_set = {};
  bool no_odometry_gate = false;  // --odometry-gate none
  std::optional<mapping::OdometryGate> odometry_gate = {};
  std::optional<std::size_t> min_separation = {};
  std::optional<std::size_t> contrast_window = {};
  std::optional<bool> reverse = {};
  std::optional<bool> graph_cleanup = {};
  std::optional<bool> odometry_evidence = {};
};
MapSettings apply_overrides(MapSettings preset, const MapOverrides& overrides);
// The part of them the shared sections take (align/settings.hpp): the offline map's, and map --online's.
void apply_section_overrides(align::ScoreSettings& score, align::SearchSettings& search,
                             align::SignificanceSettings& significance, const MapOverrides& overrides);

// Why `request` cannot run streamed, as the error its engine option earns (subject: the option that stands in the
// way), or nullopt when it can. Only what the user chose stands in the way: descriptors not asked for are adapted
// (streaming_settings, engine_choice.hpp).
std::optional<InputError> streaming_obstacle(const MapRequest& request, InputKind kind);

// Every refusal of `request` that needs no file read beyond its first session's kind (`kind`): no session, the
// streaming obstacles when the engine streams, sparse options without the sparse engine, an N x N ground truth
// with a streaming engine. Throws InputError naming the option.
void check_request(const MapRequest& request, InputKind kind);

}  // namespace seqtopo::pipeline
