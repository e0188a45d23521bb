#pragma once
// What `seqtopo map` computed, and how it is written: JSON/CSV files, figures, report.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/evaluation/topology_metrics.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/plot/matrix_overview.hpp"

namespace seqtopo::cli {

struct TrajectoryErrors {
  double odometry = 0, ekf = 0, pose_graph = 0;  // [m]
};

struct MapRun {
  std::string input, preset;
  mapping::MapConfig map_config;
  bool paper_metric = false;
  std::vector<pipeline::SimilarityResult> similarities;  // one per descriptor (kappa, names, timings)
  std::vector<SimilarityMatrix> matrices;                // their matrices, moved out of `similarities`
  std::vector<std::string> descriptor_names;
  mapping::MapResult result;
  std::vector<Pose2> odometry, ekf, pose_graph;
  std::optional<evaluation::LoopClosureMetrics> metrics, baseline_metrics;
  std::string baseline_name;
  std::string baseline_skipped;  // why the baseline did not run (--streaming), when it did not
  std::optional<TrajectoryErrors> ate;
  std::optional<evaluation::TopologyMetrics> topology;
  std::vector<std::pair<std::string, double>> timings;  // stage, seconds
  // --streaming: no matrix is held (`matrices` and result.scores are empty); similarity.png draws this
  // block-max overview of the aligned scores instead, and the report states what the streaming cost.
  bool streaming = false;
  plot::MatrixOverview overview;
  std::uint64_t streamed_cells = 0;      // similarity cells computed by the alignment, recomputations included
  std::size_t streamed_cache_bytes = 0;  // the tile cache's capacity [bytes]
};

// map.json, alignments.json, loop_closures.csv, similarity.npy, scores.npy, similarity.png,
// topology.dot/.svg, metric_map.png, pr_curve.png, metrics.json (each when it applies; with --streaming no
// similarity.npy nor scores.npy).
void write_map_outputs(const MapRun& run, io::OutputDirectory& out);
// report.html from the staged files.
void write_report(const MapRun& run, io::OutputDirectory& out);

}  // namespace seqtopo::cli
