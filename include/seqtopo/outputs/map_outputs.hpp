#pragma once
// How a map run is written (INTERFACE.md, `seqtopo map` outputs): map.json, alignments.json,
// loop_closures.csv, similarity.npy, scores.npy, similarity.png, topology.dot/.svg, metric_map.png,
// pr_curve.png, metrics.json (each when it applies; streamed runs have no similarity.npy nor scores.npy),
// and report.html over them.
#include <cstddef>
#include <optional>

#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/report_options.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"

namespace seqtopo::outputs {

// topology.svg draws maps of at most this many places place by place; larger ones (more than a layout can
// place legibly) as their collapsed graph: junctions and path ends as nodes, each path segment one edge
// labelled with its number of places.
inline constexpr std::size_t kMaxDrawnPlaces = 300;

// similarity.npy and scores.npy (N x N float32 each, 800 MB together at 10^4 images) are optional outputs:
// `matrices` true writes them, false skips them, unset (the default) writes them up to kMaxAutoMatrixImages images.
inline constexpr std::size_t kMaxAutoMatrixImages = 5000;
struct MapOutputOptions {
  std::optional<bool> matrices = std::nullopt;
};
// Whether a run of `images` images writes the two matrices.
bool writes_matrices(std::size_t images, std::optional<bool> asked);

// Every file but the report, staged in `out`. Also, with odometry, the corrected trajectory as
// trajectory_tum.txt and trajectory_kitti.txt (formats/pose_files.hpp).
void write_map_outputs(const pipeline::MapRun& run, io::OutputDirectory& out, const MapOutputOptions& options = {});
// report.html from the staged files (map_report.cpp): interactive (report/interactive.hpp) when D3 is installed,
// else static, with the result's warning saying why.
ReportResult write_map_report(const pipeline::MapRun& run, io::OutputDirectory& out, const ReportOptions& options = {});

}  // namespace seqtopo::outputs
