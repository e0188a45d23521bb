#include "seqtopo/pipeline/map_pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/baselines.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/similarity/memory.hpp"
#include "seqtopo/trajectory/ekf_map.hpp"
#include "seqtopo/trajectory/pose_graph.hpp"
#include "seqtopo/trajectory/trajectory_error.hpp"

namespace seqtopo::pipeline {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void say(const MapObserver& observer, const std::string& text) {
  if (observer.progress) observer.progress(text);
}

// The timing and the one progress line of the map stage, the same for every path.
void report_map(MapRun& run, const MapObserver& observer) {
  run.timings.emplace_back("pruning + labels + topology", run.result.seconds_prune_label);
  say(observer, fmt::format("      {} alignments ({} contradicted by odometry), {} kept, {} places, {} junctions",
                            run.result.alignments.size() + run.result.rejected.size(), run.result.rejected.size(),
                            std::count(run.result.pruning.kept.begin(), run.result.pruning.kept.end(), true),
                            run.result.map.places.size(), run.result.map.junctions.size()));
}

void check_odometry(std::span<const Pose2> odometry, std::size_t n, const std::string& subject) {
  if (!odometry.empty() && odometry.size() != n) {
    throw InputError(subject, fmt::format("has {} poses, the sequence has {} images", odometry.size(), n));
  }
}

// Stages 1 and 2 with the N x N matrices: one similarity matrix per descriptor, fused and aligned.
void map_dense(const MapRequest& request, InputKind kind, const std::vector<Pose2>& odometry,
               const MapObserver& observer, MapRun& run) {
  const MapSettings& settings = request.settings;
  auto descriptors = settings.descriptors;
  // A descriptors.npy or similarity.npy input is one matrix, whatever descriptors were asked for.
  if (kind == InputKind::descriptors || kind == InputKind::similarity) descriptors.resize(1);
  say(observer, "[1/4] similarity matrix");
  auto t = std::chrono::steady_clock::now();
  for (auto descriptor : descriptors) {
    auto config = settings.similarity;
    config.descriptor = descriptor;
    if (!config.note && observer.progress) config.note = observer.progress;
    run.similarities.push_back(compute_similarity(request.input, config));
    run.descriptor_names.emplace_back(kind == InputKind::similarity    ? "similarity.npy"
                                      : kind == InputKind::descriptors ? "descriptors.npy"
                                                                       : descriptor_name(descriptor));
    run.matrices.push_back(std::move(run.similarities.back().similarity));  // kept once, in run.matrices
    say(observer, fmt::format("      {}: {} images, kappa {:.4g}", run.descriptor_names.back(),
                              run.matrices.back().rows, run.similarities.back().kappa));
  }
  run.timings.emplace_back("similarity", seconds_since(t));
  const std::size_t n = run.matrices.front().rows;
  if (n < 2) throw InputError(request.input.path.string(), "needs at least 2 images");

  say(observer, "[2/4] alignments, pruning, labels, topology");
  check_odometry(odometry, n, request.odometry.string());
  run.result = mapping::build_map(run.matrices, settings.map, odometry);
  run.timings.emplace_back("alignment", run.result.seconds_align);
  report_map(run, observer);
}

// The streamed replacement of stages 1 and 2: descriptors, then the map on scores computed when the engine
// reads them. Leaves run.result.scores empty and fills run.overview for similarity.png.
void map_streamed(const MapRequest& request, const std::vector<Pose2>& odometry, const MapObserver& observer,
                  MapRun& run) {
  const MapSettings& settings = request.settings;
  say(observer, "[1/4] descriptors (--streaming: the similarity is computed on the fly, never N x N)");
  auto t = std::chrono::steady_clock::now();
  auto config = settings.similarity;
  config.descriptor = settings.descriptors.front();
  DescriptorResult described = compute_descriptors(request.input, config);
  const std::size_t n = described.descriptors.rows, dim = described.descriptors.cols;
  run.descriptor_names.emplace_back(
      described.descriptor == Descriptor::npy ? "descriptors.npy" : std::string(descriptor_name(described.descriptor)));
  say(observer, fmt::format("      {}: {} images, {} dimensions", run.descriptor_names.back(), n, dim));
  if (n < 2) throw InputError(request.input.path.string(), "needs at least 2 images");
  check_odometry(odometry, n, request.odometry.string());
  std::optional<scale::StreamingSimilarity> streamed;
  try {
    streamed.emplace(described.descriptors.values, n, dim,
                     scale::StreamingConfig{.contrast_window = settings.map.contrast_window,
                                            .contrast_offset = settings.map.contrast_offset});
  } catch (const std::invalid_argument& e) {
    throw InputError(request.input.path.string(), e.what());  // e.g. an all-zero descriptor has no direction
  }
  described.descriptors = {};  // the streamed similarity keeps its own normalised copy
  run.timings.emplace_back("descriptors", seconds_since(t));

  say(observer, "[2/4] alignments (fast engine on streamed scores), pruning, labels, topology");
  run.result = mapping::build_map_from_scores(streamed->source(), settings.map, odometry);
  run.timings.emplace_back("alignment (similarity streamed)", run.result.seconds_align);
  report_map(run, observer);

  const auto stats = streamed->stats();
  run.streamed_cells = stats.cells_computed;
  run.streamed_cache_bytes = stats.cache_bytes;

  say(observer, "      similarity overview for similarity.png (one more streamed pass over the lower triangle)");
  t = std::chrono::steady_clock::now();
  // The streamed scores are 0.5 (E + E^T) - offset, symmetric bit for bit: half the reads suffice.
  run.overview = plot::matrix_overview(streamed->source(), {.max_side = 2048, .symmetric = true});
  run.timings.emplace_back("similarity overview (streamed)", seconds_since(t));
}

// Stages 3 and 4: the trajectory picture and the accuracy against whatever truth is given.
void trajectory_and_accuracy(const MapSettings& settings, const MapTruth& truth, const MapObserver& observer,
                             MapRun& run) {
  const std::size_t n = run.result.map.labels.size();
  auto t = std::chrono::steady_clock::now();
  if (!run.odometry.empty()) {
    say(observer, "[3/4] metric picture (EKF and pose graph)");
    run.ekf = trajectory::ekf_map(run.odometry, run.result.map.labels).images;
    std::vector<std::pair<std::size_t, std::size_t>> loops;
    for (const auto& p : run.result.pruning.pairs) loops.emplace_back(p.i, p.j);
    run.pose_graph = trajectory::pose_graph(run.odometry, loops);
    run.timings.emplace_back("metric picture", seconds_since(t));
  }

  if (truth.same_place) {
    say(observer, "[4/4] accuracy against the ground truth");
    std::vector<evaluation::ScoredPair> pairs;
    for (const auto& p : run.result.pruning.pairs) pairs.push_back({p.i, p.j, p.score});
    run.metrics = evaluation::evaluate_loop_closures(pairs, n, truth.same_place, settings.map.min_separation);
    if (run.streaming) {
      run.baseline_skipped = "the SeqSLAM-style baseline needs the dense N x N matrix; not run with --streaming";
    } else {
      // The baseline runs on every matrix seqtopo saw (each descriptor's S and the fused, enhanced scores).
      std::vector<std::pair<std::string, const SimilarityMatrix*>> sources;
      for (std::size_t k = 0; k < run.matrices.size(); ++k)
        sources.emplace_back(run.descriptor_names[k], &run.matrices[k]);
      if (run.matrices.size() > 1 || settings.map.contrast_window > 0) {
        sources.emplace_back("seqtopo's fused scores", &run.result.scores);
      }
      if (auto b = seqslam_loop_closure_baseline(sources, n, truth.same_place, settings.map.min_separation,
                                                 settings.similarity.threads)) {
        run.baseline_metrics = std::move(b->metrics);
        run.baseline_name = std::move(b->method);
      }
    }
  }
  if (!truth.places.empty()) {
    if (truth.places.size() != n) throw std::invalid_argument("true places: one per image expected");
    // Merges of neighbouring true places that the loop-closure ground truth calls the same place are tolerated.
    const evaluation::Tolerated tolerated =
        truth.same_place ? evaluation::Tolerated(truth.same_place) : evaluation::Tolerated{};
    run.topology = evaluation::evaluate_topology(run.result.map.labels, run.result.map.junctions, truth.places,
                                                 truth.junctions, settings.map.min_separation, 2, tolerated);
  }
  if (!truth.poses.empty() && !run.odometry.empty()) {
    if (truth.poses.size() != n) throw std::invalid_argument("true poses: one per image expected");
    run.ate = TrajectoryErrors{trajectory::absolute_trajectory_error(run.odometry, truth.poses),
                               trajectory::absolute_trajectory_error(run.ekf, truth.poses),
                               trajectory::absolute_trajectory_error(run.pose_graph, truth.poses)};
  }
}

MapRun new_run(const MapSettings& settings, std::string input, std::string preset) {
  MapRun run;
  run.input = std::move(input);
  run.preset = std::move(preset);
  run.map_config = settings.map;
  run.paper_trajectory = settings.paper_trajectory;
  return run;
}

}  // namespace

MapJob::MapJob(MapRequest request) : request_(std::move(request)) {
  if (!std::filesystem::exists(request_.input.path)) {
    throw InputError(request_.input.path.string(), "no such file or folder");
  }
  for (const auto* path :
       {&request_.odometry, &request_.truth.same_place, &request_.truth.poses, &request_.truth.places}) {
    if (!path->empty() && !std::filesystem::exists(*path)) throw InputError(path->string(), "no such file");
  }
  kind_ = resolve_input_kind(request_.input);
  // The number of images, where it is known without decoding anything (not for a video).
  std::optional<std::size_t> expected;
  if (kind_ == InputKind::images) expected = list_images(request_.input.path).size();
  if (kind_ == InputKind::descriptors || kind_ == InputKind::similarity) {
    const auto header = io::read_npy_header(request_.input.path);
    if (!header.shape.empty()) expected = header.shape[0];
    if (kind_ == InputKind::similarity && (header.shape.size() != 2 || header.shape[0] != header.shape[1])) {
      throw InputError(request_.input.path.string(), "a similarity matrix for map must be square (N x N)");
    }
  }
  if (!request_.odometry.empty()) {
    odometry_ = formats::read_odometry_csv(request_.odometry);
    if (expected) check_odometry(odometry_, *expected, request_.odometry.string());
  }
  // Every buffer of the run counted (memory_estimate.hpp); one that cannot fit is refused here, before any work.
  // (A video's frames are counted only while it is read: the similarity step estimates its matrix then.)
  if (expected) {
    memory_note_ = check_map_memory(request_, kind_, *expected, similarity::available_memory_bytes());
    request_.settings.similarity.note_memory_above = std::numeric_limits<std::size_t>::max();  // ours is printed
  }
}

MapRun MapJob::run(const MapObserver& observer) const {
  MapRun run = new_run(request_.settings, request_.input.path.string(), request_.preset);
  if (!memory_note_.empty()) say(observer, "      " + memory_note_);
  run.streaming = request_.streaming;
  run.odometry = odometry_;
  if (request_.streaming) {
    map_streamed(request_, odometry_, observer, run);
  } else {
    map_dense(request_, kind_, odometry_, observer, run);
  }
  const std::size_t n = run.result.map.labels.size();
  MapTruth truth;
  const auto& files = request_.truth;
  if (!files.same_place.empty()) truth.same_place = load_same_place(files.same_place, files.radius, n);
  if (!files.places.empty()) {
    auto places = load_true_places(files.places, n);
    truth.places = std::move(places.places);
    truth.junctions = std::move(places.junctions);
  }
  if (!files.poses.empty() && !run.odometry.empty()) truth.poses = load_true_poses(files.poses, n);
  trajectory_and_accuracy(request_.settings, truth, observer, run);
  return run;
}

MapRun map_sequence(const MapRequest& request, const MapObserver& observer) { return MapJob(request).run(observer); }

MapRun map_similarities(std::vector<SimilarityMatrix> similarities, std::vector<std::string> names,
                        const MapSettings& settings, std::span<const Pose2> odometry, const MapTruth& truth,
                        const MapObserver& observer) {
  if (similarities.empty()) throw std::invalid_argument("no similarity matrix");
  if (!names.empty() && names.size() != similarities.size()) {
    throw std::invalid_argument("one name per similarity matrix expected");
  }
  MapRun run = new_run(settings, "memory", "custom");
  for (std::size_t k = 0; k < similarities.size(); ++k) {
    run.descriptor_names.push_back(names.empty() ? fmt::format("similarity {}", k) : names[k]);
  }
  run.matrices = std::move(similarities);
  const std::size_t n = run.matrices.front().rows;
  if (!odometry.empty() && odometry.size() != n) {
    throw std::invalid_argument(fmt::format("odometry has {} poses, the sequence has {} images", odometry.size(), n));
  }
  run.odometry.assign(odometry.begin(), odometry.end());
  say(observer, "[2/4] alignments, pruning, labels, topology");
  run.result = mapping::build_map(run.matrices, settings.map, odometry);
  run.timings.emplace_back("alignment", run.result.seconds_align);
  report_map(run, observer);
  trajectory_and_accuracy(settings, truth, observer, run);
  return run;
}

}  // namespace seqtopo::pipeline
