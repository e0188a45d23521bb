#pragma once
// `seqtopo map` as one library call; the command line and the Python module are thin over it.
//
//   sequence (image folder, video, descriptors.npy, similarity.npy)
//     -> similarity matrices (one per descriptor)            sequence_similarity.hpp
//     -> fused, contrast-enhanced scores -> alignments -> pruning -> places -> topology   mapping/map_builder.hpp
//     -> trajectory picture (EKF, pose graph) with odometry  trajectory/
//     -> accuracy against the ground truth, and the SeqSLAM-style baseline on the same matrices
//
//   pipeline::MapRequest request;
//   request.sessions = {pipeline::SessionSource{{"data/rtabmap-corridor"}}};     // map_request.hpp
//   request.truth.same_place = "data/rtabmap-corridor/ground_truth.bmp";
//   pipeline::MapRun run = pipeline::map_sequence(request);   // run.result.map, run.metrics->f1
//
// In memory (arrays from Python or another sensor): map_similarities() takes the matrices and the truth.
// Writing the results (map.json, figures, report) is the outputs module's job (outputs/map_outputs.hpp).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/evaluation/calibration.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/evaluation/topology_metrics.hpp"
#include "seqtopo/formats/map_json.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/map_request.hpp"
#include "seqtopo/pipeline/presets.hpp"
#include "seqtopo/pipeline/progress.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/pipeline/session_input.hpp"
#include "seqtopo/plot/matrix_overview.hpp"
#include "seqtopo/timeline/session_breaks.hpp"

namespace seqtopo::pipeline {

// The ground truth a map is scored against, in memory; every part is optional.
struct MapTruth {
  evaluation::SamePlace same_place;              // loop closures
  evaluation::EarlierPartners earlier_partners;  // optional: the recall denominator without testing every pair
  std::vector<int> places;                       // true place of every image (topology)
  std::vector<int> junctions;                    // true junction places
  std::vector<Pose2> poses;                      // true poses (trajectory error, with odometry)
};

struct TrajectoryErrors {
  double odometry = 0, ekf = 0, pose_graph = 0;  // [m]
};

// Everything one map run computed.
struct MapRun {
  std::string input, preset;
  SequenceInput sequence;  // what was mapped (the report's thumbnails); empty path in memory
  // Several sessions: each one's input (the report's thumbnails, session by session); `sequence` is then empty.
  std::vector<SequenceInput> session_inputs;
  // The session of every image: [begin, end) of each input, in order (one for a single input).
  std::vector<formats::MapSession> sessions;
  // Breaks found inside the inputs (a long gap in their frames' times with frames either side unlike neighbours:
  // timeline/session_breaks.hpp), each the first frame of a new session of the map; `frame` counts over the
  // sessions.
  std::vector<timeline::TimeGap> session_breaks;
  // `sessions` split at `session_breaks`: the map's sessions (map.json).
  std::vector<formats::MapSession> map_sessions() const;
  mapping::MapConfig map_config;
  bool paper_trajectory = false;
  std::vector<SimilarityResult> similarities;  // one per descriptor (kappa, names, timings)
  std::vector<SimilarityMatrix> matrices;      // their matrices, moved out of `similarities`
  std::vector<std::string> descriptor_names;
  mapping::MapResult result;
  std::vector<Pose2> odometry, ekf, pose_graph;
  std::optional<evaluation::LoopClosureMetrics> metrics, baseline_metrics;
  // With a same-place ground truth: the false positives and missed revisits behind `metrics` (the report marks them).
  std::optional<evaluation::LoopClosureErrors> errors;
  // The retained pairs' confidence against the ground truth (every pair, not only each image's best).
  std::optional<evaluation::Calibration> calibration;
  std::string baseline_name;
  std::string baseline_skipped;  // why the baseline did not run (streaming), when it did not
  std::optional<TrajectoryErrors> ate;
  std::optional<evaluation::TopologyMetrics> topology;
  // Stage, seconds: the parts of run(), one after the other, so they add up to its wall time (the command line
  // appends its own: setup, files and figures, report).
  std::vector<std::pair<std::string, double>> timings;
  MapEngine engine = MapEngine::exact;  // the engine that ran (map_request.hpp; never automatic)
  bool streamed() const { return streams(engine); }
  // Streamed: no matrix is held (`matrices` and result.scores are empty); similarity.png draws this
  // block-max overview of the aligned scores instead, and the report states what the streaming cost.
  plot::MatrixOverview overview;
  std::uint64_t streamed_cells = 0;      // similarity cells computed by the alignment, recomputations included
  std::size_t streamed_cache_bytes = 0;  // the tile cache's capacity [bytes]
  std::size_t sparse_pairs = 0;          // --sparse: candidate cells aligned (both triangles)
};

// Lines about the work as it goes (stages, sizes, memory estimates); the library never prints.
//
// `progress` gets text lines; with `stage` set, the stages come as structured events instead
// (pipeline/progress.hpp: plan, begin, advance with done / total, end with the stage's time) and `progress`
// only gets the detail lines. `later_stages` names stages the caller runs after the job (writing the files,
// the report), numbered after the job's own in the plan so that the numbering is the same from start to end.
struct MapObserver {
  // Default member initializers: `{.progress = ...}` alone stays free of -Wmissing-field-initializers.
  std::function<void(std::string_view)> progress = {};
  StageObserver stage = {};
  std::vector<std::string> later_stages = {};
  // A single image folder's images as they are read (index, pixels), from the describing threads one call at a time
  // per image, in any order: the report's thumbnails (outputs::ThumbnailCollector), which then need not be decoded
  // again.
  std::function<void(std::size_t, const RgbImage&)> on_image = {};
};

// A checked request: the constructor checks it (check_request), reads what is small (the odometry, the number of
// images where it is known without decoding), resolves its engine (engine_choice.hpp) and throws InputError on
// anything wrong, before any long work, a run whose memory estimate (memory_estimate.hpp) exceeds the memory
// available included; run() does the work.
class MapJob {
 public:
  explicit MapJob(MapRequest request);
  MapRun run(const MapObserver& observer = {}) const;
  InputKind input_kind() const { return kind_; }        // of the first session
  MapEngine engine() const { return request_.engine; }  // resolved: never automatic
  const std::vector<PreparedSession>& sessions() const { return sessions_; }

 private:
  MapRequest request_;
  InputKind kind_;
  std::vector<PreparedSession> sessions_;
  std::vector<SequenceInput> inputs_;          // the sessions' inputs, with their kept frames
  std::vector<Pose2> odometry_;                // all sessions', concatenated
  std::string memory_note_;                    // the whole run's memory estimate (memory_estimate.hpp)
  std::string panorama_note_;                  // the descriptors chosen for 360-degree panoramas (presets.hpp)
  std::string engine_note_;                    // the engine chosen, and the settings adapted to streaming
  std::optional<GroundTruthFile> same_place_;  // request.truth.same_place, read and checked before the work
  // The step a ground truth of the whole recording is thinned by (one input thinned by --every alone).
  std::size_t truth_every() const;
};

// MapJob(request).run(observer).
MapRun map_sequence(const MapRequest& request, const MapObserver& observer = {});

// The pipeline from similarity matrices already in memory (one per descriptor, all N x N; several are fused),
// named for the report (`names`, one per matrix, may be empty). `odometry` has one pose per image or is empty.
// Throws std::invalid_argument on sizes that disagree.
MapRun map_similarities(std::vector<SimilarityMatrix> similarities, std::vector<std::string> names,
                        const MapSettings& settings, std::span<const Pose2> odometry = {}, const MapTruth& truth = {},
                        const MapObserver& observer = {});

}  // namespace seqtopo::pipeline
