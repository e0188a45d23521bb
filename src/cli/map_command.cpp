// seqtopo map: the main job (INTERFACE.md). Sequence -> similarity -> forward and reverse alignments ->
// pruning -> labels -> topological map -> metric picture -> figures, metrics and report.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command_registry.hpp"
#include "map_outputs.hpp"
#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/evaluation/topology_metrics.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/formats/places_csv.hpp"
#include "seqtopo/image/grey_matrix_file.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/plot/matrix_overview.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/trajectory/ekf_map.hpp"
#include "seqtopo/trajectory/pose_graph.hpp"
#include "seqtopo/trajectory/trajectory_error.hpp"

namespace seqtopo::cli {
namespace {
namespace fs = std::filesystem;

struct MapOptions {
  std::string input;
  std::string out = "seqtopo-out";
  std::string input_kind = "auto";
  std::size_t every = 1;
  std::string preset = "default";
  std::optional<std::string> descriptor, metric_name, kappa;
  std::optional<float> gap, threshold;
  std::optional<std::string> cap, odometry_gate;
  std::optional<std::string> engine;  // default exact, fast with --streaming
  std::optional<std::size_t> min_separation, contrast_window;
  std::optional<float> contrast_offset;
  bool no_reverse = false;
  bool streaming = false;
  std::string odometry, ground_truth, gt_places, gt_poses;
  std::optional<double> gt_radius;
  unsigned threads = 0;
  std::string config_file;
};

// The preset fixes the defaults; every explicit option overrides them.
struct Settings {
  pipeline::SimilarityConfig similarity;
  // One similarity matrix per descriptor; several are fused (mapping::build_map).
  std::vector<pipeline::Descriptor> descriptors{pipeline::Descriptor::joint_histogram, pipeline::Descriptor::patch};
  mapping::MapConfig map;
  bool paper_metric = false;  // the paper's EKF is the metric picture (else the pose graph)
};

Settings resolve_settings(const MapOptions& o) {
  Settings s;
  if (o.preset == "paper") {
    s.descriptors = {pipeline::Descriptor::joint_histogram};
    s.similarity.distance = pipeline::Distance::chi2;
    s.paper_metric = true;
    s.map.contrast_window = 0;                                             // the paper aligns S = 1 - kappa D as it is
    s.map.pruning.rank = mapping::PruningConfig::Rank::length_then_score;  // "the longest matching subsequence"
    // Raw S lives on another scale than enhanced scores; these were tuned on the corridor with kappa
    // auto (bench/tune_map.cpp): F1 0.872, AUC 0.773.
    s.map.gap = 0.3F;
    s.map.cap = 8.0F;
    s.map.threshold = 3.0F;
  } else if (o.preset != "default") {
    throw InputError("--preset", "unknown preset '" + o.preset + "' (paper or default)");
  }
  if (o.descriptor) {
    s.descriptors = option_value("--descriptor", [&] {
      std::vector<pipeline::Descriptor> list;
      std::stringstream names(*o.descriptor);
      for (std::string name; std::getline(names, name, ',');) list.push_back(pipeline::parse_descriptor(name));
      if (list.empty()) throw std::invalid_argument("no descriptor given");
      return list;
    });
  }
  if (o.metric_name)
    s.similarity.distance = option_value("--metric", [&] { return similarity::parse_distance(*o.metric_name); });
  if (o.kappa && *o.kappa != "auto") {
    try {
      s.similarity.kappa = std::stof(*o.kappa);
    } catch (const std::exception&) {
      throw InputError("--kappa", "expected a number or 'auto', got '" + *o.kappa + "'");
    }
    if (!(*s.similarity.kappa > 0)) throw InputError("--kappa", "must be > 0");
  }
  s.similarity.threads = o.threads;
  s.similarity.note = [](std::string_view text) { std::cerr << "seqtopo map: " << text << "\n"; };
  if (o.gap) {
    if (!(*o.gap >= 0)) throw InputError("--gap", "must be >= 0");
    s.map.gap = *o.gap;
  }
  if (o.threshold) {
    if (!(*o.threshold > 0)) throw InputError("--threshold", "must be > 0");
    s.map.threshold = *o.threshold;
  }
  if (o.cap) {
    if (*o.cap == "none") {
      s.map.cap.reset();
    } else {
      try {
        s.map.cap = std::stof(*o.cap);
      } catch (const std::exception&) {
        throw InputError("--cap", "expected a number or 'none', got '" + *o.cap + "'");
      }
      if (!(*s.map.cap > 0)) throw InputError("--cap", "must be > 0");
    }
  }
  const std::string engine = o.engine.value_or(o.streaming ? "fast" : "exact");
  if (engine == "fast") {
    s.map.engine = mapping::MapConfig::Engine::fast;
  } else if (engine != "exact") {
    throw InputError("--engine", "expected exact or fast, got '" + engine + "'");
  }
  if (o.odometry_gate) {
    s.map.odometry_gate = option_value("--odometry-gate", [&]() -> std::optional<mapping::OdometryGate> {
      if (*o.odometry_gate == "none") return std::nullopt;
      mapping::OdometryGate gate;
      char comma = 0;
      std::istringstream in(*o.odometry_gate);
      if (!(in >> gate.base >> comma >> gate.drift) || comma != ',' || !in.eof() || !(gate.base >= 0) ||
          !(gate.drift >= 0)) {
        throw std::invalid_argument(
            "expected BASE,DRIFT (metres, metres per metre travelled, both >= 0) or none, got '" + *o.odometry_gate +
            "'");
      }
      return gate;
    });
  }
  if (o.min_separation) {
    if (*o.min_separation == 0) throw InputError("--min-separation", "must be >= 1");
    s.map.min_separation = *o.min_separation;
  }
  if (o.contrast_window) s.map.contrast_window = *o.contrast_window;
  if (o.contrast_offset) s.map.contrast_offset = *o.contrast_offset;
  s.map.reverse = !o.no_reverse;
  s.map.threads = resolve_threads(o.threads);
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void progress(const std::string& text) { std::cerr << "seqtopo map: " << text << std::endl; }

// The same-place relation of the ground truth, from an N x N image or from poses and a radius.
evaluation::SamePlace load_ground_truth(const MapOptions& o, const std::string& path, std::size_t images) {
  if (fs::path(path).extension() == ".csv") {
    if (!o.gt_radius || !(*o.gt_radius > 0))
      throw InputError("--gt-radius", "needed (> 0) with a poses.csv ground truth");
    const auto poses = formats::read_poses_csv(path);
    if (poses.size() != images) {
      throw InputError(path, fmt::format("has {} poses, the sequence has {} images", poses.size(), images));
    }
    const double r2 = *o.gt_radius * *o.gt_radius;
    return [poses, r2](std::size_t i, std::size_t j) {
      const double dx = poses[i].x - poses[j].x, dy = poses[i].y - poses[j].y;
      return dx * dx + dy * dy <= r2;
    };
  }
  auto m = std::make_shared<DenseMatrix<std::uint8_t>>(image::read_grey_matrix_image(path));
  if (m->rows != images || m->cols != images) {
    throw InputError(path, fmt::format("is {} x {}, the sequence has {} images", m->rows, m->cols, images));
  }
  return [m](std::size_t i, std::size_t j) { return (*m)(i, j) != 0 || (*m)(j, i) != 0; };
}

// The timing and the one progress line of the map stage, the same for both paths.
void report_map(MapRun& run) {
  run.timings.emplace_back("pruning + labels + topology", run.result.seconds_prune_label);
  progress(fmt::format("      {} alignments ({} contradicted by odometry), {} kept, {} places, {} junctions",
                       run.result.alignments.size() + run.result.rejected.size(), run.result.rejected.size(),
                       std::count(run.result.pruning.kept.begin(), run.result.pruning.kept.end(), true),
                       run.result.map.places.size(), run.result.map.junctions.size()));
}

// --streaming aligns contrast-enhanced cosine scores of one vector descriptor per image, computed on the
// fly (scale/streaming_similarity.hpp); whatever needs the N x N matrix is refused here, before any work.
void check_streaming(const MapOptions& o, const Settings& s, pipeline::InputKind kind) {
  if (o.preset == "paper") {
    throw InputError("--preset",
                     "paper aligns the raw S = 1 - kappa D, whose kappa needs the whole distance matrix; "
                     "--streaming never holds it (use the default preset)");
  }
  if (s.map.engine != mapping::MapConfig::Engine::fast) {
    throw InputError("--engine", "exact fills an N x N table; --streaming needs the fast engine (its default)");
  }
  if (kind == pipeline::InputKind::similarity) {
    throw InputError("--streaming",
                     "needs descriptors (descriptors.npy, or images with one vector descriptor), "
                     "not a similarity matrix");
  }
  if (s.map.contrast_window == 0) {
    throw InputError("--contrast-window",
                     "0 aligns the raw S = 1 - kappa D, whose kappa needs the whole distance "
                     "matrix; --streaming aligns contrast-enhanced scores (window >= 1)");
  }
  if (o.kappa) throw InputError("--kappa", "has no effect with --streaming: the contrast enhancement removes kappa");
  if (o.metric_name && s.similarity.distance != pipeline::Distance::cosine) {
    throw InputError("--metric", "--streaming scores by cosine similarity only, got '" + *o.metric_name + "'");
  }
  if (o.descriptor && s.descriptors.size() != 1) {
    throw InputError("--descriptor", fmt::format("--streaming takes one descriptor, got {} (fusing needs one N x N "
                                                 "matrix per descriptor)",
                                                 s.descriptors.size()));
  }
  if (kind != pipeline::InputKind::descriptors) {  // images or a video: the descriptor is computed
    if (!o.descriptor) {
      throw InputError("--descriptor",
                       "--streaming needs one vector descriptor for images (patch or panorama, with "
                       "--metric cosine); the default fuses joint-histogram and patch");
    }
    if (s.descriptors.front() == pipeline::Descriptor::npy) {
      throw InputError("--descriptor", "npy needs a descriptors.npy input");
    }
    if (s.descriptors.front() == pipeline::Descriptor::joint_histogram) {
      throw InputError("--descriptor",
                       "joint-histogram is a sparse histogram without a vector form; --streaming "
                       "needs patch or panorama (with --metric cosine)");
    }
    if (!o.metric_name) {
      throw InputError("--metric", "--streaming scores by cosine similarity: give --metric cosine (" +
                                       std::string(pipeline::descriptor_name(s.descriptors.front())) +
                                       " defaults to sad)");
    }
  }
  if (!o.ground_truth.empty()) {
    if (fs::path(o.ground_truth).extension() != ".csv") {
      throw InputError("--ground-truth",
                       "an N x N image (N^2 bytes, 10 GB at 10^5 images) is refused with "
                       "--streaming; give poses.csv with --gt-radius");
    }
    if (!o.gt_radius || !(*o.gt_radius > 0))
      throw InputError("--gt-radius", "needed (> 0) with a poses.csv ground truth");
  }
}

// The streamed replacement of stages 1 and 2: descriptors, then the map on scores computed when the engine
// reads them. Leaves run.result.scores empty and fills run.overview for similarity.png.
void map_streamed(const MapOptions& o, const Settings& settings, const pipeline::SequenceInput& input, MapRun& run) {
  progress("[1/4] descriptors (--streaming: the similarity is computed on the fly, never N x N)");
  auto t = std::chrono::steady_clock::now();
  auto config = settings.similarity;
  config.descriptor = settings.descriptors.front();
  pipeline::DescriptorResult described = pipeline::compute_descriptors(input, config);
  const std::size_t n = described.descriptors.rows, dim = described.descriptors.cols;
  run.descriptor_names.emplace_back(described.descriptor == pipeline::Descriptor::npy
                                        ? "descriptors.npy"
                                        : std::string(pipeline::descriptor_name(described.descriptor)));
  progress(fmt::format("      {}: {} images, {} dimensions", run.descriptor_names.back(), n, dim));
  if (n < 2) throw InputError(o.input, "needs at least 2 images");
  if (!run.odometry.empty() && run.odometry.size() != n) {
    throw InputError(o.odometry, fmt::format("has {} poses, the sequence has {} images", run.odometry.size(), n));
  }
  std::optional<scale::StreamingSimilarity> streamed;
  try {
    streamed.emplace(described.descriptors.values, n, dim,
                     scale::StreamingConfig{.contrast_window = settings.map.contrast_window,
                                            .contrast_offset = settings.map.contrast_offset});
  } catch (const std::invalid_argument& e) {
    throw InputError(o.input, e.what());  // e.g. an all-zero descriptor has no direction
  }
  described.descriptors = {};  // the streamed similarity keeps its own normalised copy
  run.timings.emplace_back("descriptors", seconds_since(t));

  progress("[2/4] alignments (fast engine on streamed scores), pruning, labels, topology");
  run.result = mapping::build_map_from_scores(streamed->source(), settings.map, run.odometry);
  run.timings.emplace_back("alignment (similarity streamed)", run.result.seconds_align);
  report_map(run);

  const auto stats = streamed->stats();
  run.streamed_cells = stats.cells_computed;
  run.streamed_cache_bytes = stats.cache_bytes;

  progress("      similarity overview for similarity.png (one more streamed pass over the lower triangle)");
  t = std::chrono::steady_clock::now();
  // The streamed scores are 0.5 (E + E^T) - offset, symmetric bit for bit: half the reads suffice.
  run.overview = plot::matrix_overview(streamed->source(), {.max_side = 2048, .symmetric = true});
  run.timings.emplace_back("similarity overview (streamed)", seconds_since(t));
}

// Stages 1 and 2 with the N x N matrices: one similarity matrix per descriptor, fused and aligned.
void map_dense(const MapOptions& o, const Settings& settings, const pipeline::SequenceInput& input,
               pipeline::InputKind kind, MapRun& run) {
  auto descriptors = settings.descriptors;
  // A descriptors.npy or similarity.npy input is one matrix, whatever descriptors were asked for.
  if (kind == pipeline::InputKind::descriptors || kind == pipeline::InputKind::similarity) descriptors.resize(1);
  progress("[1/4] similarity matrix");
  auto t = std::chrono::steady_clock::now();
  auto& matrices = run.matrices;
  for (auto descriptor : descriptors) {
    auto config = settings.similarity;
    config.descriptor = descriptor;
    run.similarities.push_back(pipeline::compute_similarity(input, config));
    run.descriptor_names.emplace_back(kind == pipeline::InputKind::similarity ? "similarity.npy"
                                      : kind == pipeline::InputKind::descriptors
                                          ? "descriptors.npy"
                                          : pipeline::descriptor_name(descriptor));
    matrices.push_back(std::move(run.similarities.back().similarity));  // kept once, in run.matrices
    progress(fmt::format("      {}: {} images, kappa {:.4g}", run.descriptor_names.back(), matrices.back().rows,
                         run.similarities.back().kappa));
  }
  run.timings.emplace_back("similarity", seconds_since(t));
  const std::size_t n = matrices.front().rows;
  if (n < 2) throw InputError(o.input, "needs at least 2 images");

  progress("[2/4] alignments, pruning, labels, topology");
  if (!o.odometry.empty() && run.odometry.size() != n) {
    throw InputError(o.odometry, fmt::format("has {} poses, the sequence has {} images", run.odometry.size(), n));
  }
  run.result = mapping::build_map(matrices, settings.map, run.odometry);
  run.timings.emplace_back("alignment", run.result.seconds_align);
  report_map(run);
}

void run(MapOptions o) {
  const auto total_start = std::chrono::steady_clock::now();
  MapRun run;
  // Everything the user gave is checked before the long computation starts (and before any progress
  // output), so a mistake costs one line and no time.
  const Settings settings = resolve_settings(o);
  const bool bundled_default = o.input.empty();
  if (bundled_default) {
    const fs::path bundled = fs::path(SEQTOPO_DATA_DIR) / "rtabmap-corridor";
    o.input = fs::exists(bundled) ? bundled.string() : "data/rtabmap-corridor";
    // Its ground truth is an N x N image, which --streaming refuses.
    if (o.ground_truth.empty() && !o.streaming) o.ground_truth = (fs::path(o.input) / "ground_truth.bmp").string();
  }
  if (!fs::exists(o.input)) throw InputError(o.input, "no such file or folder");
  for (const auto* path : {&o.odometry, &o.ground_truth, &o.gt_poses, &o.gt_places}) {
    if (!path->empty() && !fs::exists(*path)) throw InputError(*path, "no such file");
  }
  pipeline::SequenceInput input{o.input, pipeline::parse_input_kind(o.input_kind), o.every};
  const auto kind = pipeline::resolve_input_kind(input);
  if (o.streaming) check_streaming(o, settings, kind);
  // The number of images, where it is known without decoding anything (not for a video).
  std::optional<std::size_t> expected;
  if (kind == pipeline::InputKind::images) expected = pipeline::list_images(o.input).size();
  if (kind == pipeline::InputKind::descriptors || kind == pipeline::InputKind::similarity) {
    const auto header = io::read_npy_header(o.input);
    if (!header.shape.empty()) expected = header.shape[0];
    if (kind == pipeline::InputKind::similarity && (header.shape.size() != 2 || header.shape[0] != header.shape[1])) {
      throw InputError(o.input, "a similarity matrix for map must be square (N x N)");
    }
  }
  if (!o.odometry.empty()) {
    run.odometry = formats::read_odometry_csv(o.odometry);
    if (expected && run.odometry.size() != *expected) {
      throw InputError(o.odometry,
                       fmt::format("has {} poses, the sequence has {} images", run.odometry.size(), *expected));
    }
  }
  run.preset = o.preset;
  run.input = o.input;
  run.map_config = settings.map;
  run.paper_metric = settings.paper_metric;
  run.streaming = o.streaming;
  io::OutputDirectory out(o.out);
  if (bundled_default) progress("no input given: mapping the bundled corridor data " + o.input);
  if (bundled_default && o.streaming) progress("its ground truth is an N x N image, which --streaming does not read");
  if (o.streaming) {
    map_streamed(o, settings, input, run);
  } else {
    map_dense(o, settings, input, kind, run);
  }
  const std::size_t n = run.result.map.labels.size();
  const auto& matrices = run.matrices;

  auto t = std::chrono::steady_clock::now();
  if (!o.odometry.empty()) {
    progress("[3/4] metric picture (EKF and pose graph)");
    run.ekf = trajectory::ekf_map(run.odometry, run.result.map.labels).images;
    std::vector<std::pair<std::size_t, std::size_t>> loops;
    for (const auto& p : run.result.pruning.pairs) loops.emplace_back(p.i, p.j);
    run.pose_graph = trajectory::pose_graph(run.odometry, loops);
    run.timings.emplace_back("metric picture", seconds_since(t));
  }

  if (!o.ground_truth.empty()) {
    progress("[4/4] accuracy against the ground truth");
    const auto same_place = load_ground_truth(o, o.ground_truth, n);
    std::vector<evaluation::ScoredPair> pairs;
    for (const auto& p : run.result.pruning.pairs) pairs.push_back({p.i, p.j, p.score});
    run.metrics = evaluation::evaluate_loop_closures(pairs, n, same_place, settings.map.min_separation);
    if (o.streaming)
      run.baseline_skipped = "the SeqSLAM-style baseline needs the dense N x N matrix; not run with --streaming";
    // With --streaming no matrix was kept, so the list below is empty and the baseline does not run.

    // The baseline runs on every matrix seqtopo saw (each descriptor's S and the fused, enhanced
    // scores) and the one with the best AUC is reported, at its best-F1 threshold: the most generous
    // reading of a single-threshold sequence matcher.
    baseline::SeqSlamConfig seqslam;
    seqslam.self = true;
    seqslam.min_separation = settings.map.min_separation;
    seqslam.threads = o.threads;
    std::vector<std::pair<std::string, const SimilarityMatrix*>> sources;
    for (std::size_t k = 0; k < matrices.size(); ++k) sources.emplace_back(run.descriptor_names[k], &matrices[k]);
    if (!o.streaming && (matrices.size() > 1 || settings.map.contrast_window > 0)) {
      sources.emplace_back("seqtopo's fused scores", &run.result.scores);
    }
    for (const auto& [name, matrix] : sources) {
      std::vector<evaluation::ScoredPair> pairs;
      for (const auto& m : baseline::seqslam_matches(*matrix, seqslam)) {
        if (m.valid) pairs.push_back({m.query, m.match, m.score});
      }
      auto metrics = evaluation::evaluate_loop_closures(pairs, n, same_place, settings.map.min_separation);
      if (run.baseline_metrics && metrics.auc <= run.baseline_metrics->auc) continue;
      float best_threshold = 0;
      double best_f1 = -1;
      for (const auto& p : metrics.curve) {
        const double f1 = p.precision + p.recall > 0 ? 2 * p.precision * p.recall / (p.precision + p.recall) : 0.0;
        if (f1 > best_f1) {
          best_f1 = f1;
          best_threshold = p.threshold;
        }
      }
      std::erase_if(pairs, [&](const evaluation::ScoredPair& p) { return p.score < best_threshold; });
      const auto at_threshold = evaluation::evaluate_loop_closures(pairs, n, same_place, settings.map.min_separation);
      metrics.tp = at_threshold.tp;
      metrics.fp = at_threshold.fp;
      metrics.fn = at_threshold.fn;
      metrics.precision = at_threshold.precision;
      metrics.recall = at_threshold.recall;
      metrics.f1 = at_threshold.f1;
      run.baseline_metrics = metrics;
      run.baseline_name =
          fmt::format("SeqSLAM-style on {} (sequence {}, velocities {}-{}, best-F1 threshold {:.3g})", name,
                      seqslam.sequence_length, seqslam.min_velocity, seqslam.max_velocity, best_threshold);
    }
  }
  if (!o.gt_places.empty()) {
    const auto places = formats::read_places_csv(o.gt_places);
    if (places.size() != n)
      throw InputError(o.gt_places, fmt::format("has {} rows, the sequence has {} images", places.size(), n));
    const fs::path junctions_file = fs::path(o.gt_places).parent_path() / "junctions.csv";
    const auto true_junctions =
        fs::exists(junctions_file) ? formats::read_junctions_csv(junctions_file) : std::vector<int>{};
    // Merges of neighbouring true places that the loop-closure ground truth calls the same place are tolerated.
    const evaluation::Tolerated tolerated =
        o.ground_truth.empty() ? evaluation::Tolerated{} : load_ground_truth(o, o.ground_truth, n);
    run.topology = evaluation::evaluate_topology(run.result.map.labels, run.result.map.junctions, places,
                                                 true_junctions, settings.map.min_separation, 2, tolerated);
  }
  if (!o.gt_poses.empty() && !run.odometry.empty()) {
    const auto truth = formats::read_poses_csv(o.gt_poses);
    if (truth.size() != n)
      throw InputError(o.gt_poses, fmt::format("has {} poses, the sequence has {} images", truth.size(), n));
    run.ate = {trajectory::absolute_trajectory_error(run.odometry, truth),
               trajectory::absolute_trajectory_error(run.ekf, truth),
               trajectory::absolute_trajectory_error(run.pose_graph, truth)};
  }

  t = std::chrono::steady_clock::now();
  write_map_outputs(run, out);
  run.timings.emplace_back("figures and report", seconds_since(t));
  write_report(run, out);
  const auto written = out.commit();
  progress(fmt::format("wrote {} files to {} in {:.2f} s", written.size(), o.out, seconds_since(total_start)));
  if (run.metrics) {
    progress(fmt::format("loop closures: precision {:.3f} recall {:.3f} F1 {:.3f} AUC {:.3f} R@100P {:.3f}",
                         run.metrics->precision, run.metrics->recall, run.metrics->f1, run.metrics->auc,
                         run.metrics->recall_at_100_precision));
  }
}

const RegisterCommand registered{
    {"map",
     "The main job: image sequence -> topological map, loop closures, figures and report "
     "(with no INPUT: the bundled corridor data, scored against its ground truth)",
     [](CLI::App& app) {
       auto o = std::make_shared<MapOptions>();
       app.add_option("input", o->input, "image folder, video, descriptors.npy or similarity.npy");
       app.add_option("--out", o->out, "output folder")->capture_default_str();
       app.add_option("--input-kind", o->input_kind, "auto|images|video|descriptors|similarity")->capture_default_str();
       app.add_option("--every", o->every, "video: use every K-th frame")->capture_default_str();
       app.add_option("--preset", o->preset, "paper (joint histogram, chi2, EKF) or default")->capture_default_str();
       app.add_option("--descriptor", o->descriptor,
                      "joint-histogram|patch|panorama, or several separated by commas to fuse them "
                      "(default joint-histogram,patch; paper preset joint-histogram)");
       app.add_option("--metric", o->metric_name, "chi2|l1|cosine|sad (default: by descriptor)");
       app.add_option("--kappa", o->kappa, "S = 1 - kappa * D: a number, or auto (from the sequence's own distances)");
       app.add_option("--gap", o->gap, fmt::format("penalty per skipped image (default {})", mapping::MapConfig{}.gap));
       app.add_option("--engine", o->engine,
                      "exact (scalar reference, N x N table) or fast (vectorized, no N x N table, scores quantized "
                      "to 1/512); default exact, fast with --streaming");
       app.add_flag("--streaming", o->streaming,
                    "never hold the N x N matrix: contrast-enhanced cosine scores of one vector descriptor "
                    "(descriptors.npy, or patch/panorama with --metric cosine) computed on the fly, fast engine; "
                    "no scores.npy, similarity.npy nor SeqSLAM baseline, similarity.png a block-max overview");
       app.add_option(
           "--odometry-gate", o->odometry_gate,
           fmt::format("with --odometry: drop alignments whose images odometry puts more than BASE + DRIFT * "
                       "(metres travelled between them) apart, as BASE,DRIFT, or none (default {},{})",
                       mapping::OdometryGate{}.base, mapping::OdometryGate{}.drift));
       app.add_option("--cap", o->cap,
                      fmt::format("cap on the cumulative score, or none (default {})", *mapping::MapConfig{}.cap));
       app.add_option("--threshold", o->threshold,
                      fmt::format("minimum alignment score of a revisit (default {})", mapping::MapConfig{}.threshold));
       app.add_option("--min-separation", o->min_separation,
                      fmt::format("frames around the diagonal that never count (default {})",
                                  mapping::MapConfig{}.min_separation));
       app.add_option("--contrast-window", o->contrast_window,
                      fmt::format("local contrast enhancement before alignment, half-width in frames; 0 = off "
                                  "(default {}, paper preset 0)",
                                  mapping::MapConfig{}.contrast_window));
       app.add_option("--contrast-offset", o->contrast_offset,
                      fmt::format("enhanced scores above this many standard deviations are rewarded (default {})",
                                  mapping::MapConfig{}.contrast_offset));
       app.add_flag("--no-reverse", o->no_reverse, "do not look for paths revisited in the opposite direction");
       app.add_option("--odometry", o->odometry, "odometry CSV: index,x,y,theta (cumulative) or index,dx,dy,dtheta");
       app.add_option("--ground-truth", o->ground_truth, "N x N same-place image, or poses.csv with --gt-radius");
       app.add_option("--gt-radius", o->gt_radius, "same place when closer than this [m] (poses.csv ground truth)");
       app.add_option("--gt-places", o->gt_places, "places.csv (index,place) for topological scores");
       app.add_option("--gt-poses", o->gt_poses,
                      "poses.csv (index,x,y[,theta]) for the metric error (with --odometry)");
       app.add_option("--threads", o->threads, "worker threads (0 = all cores); results do not depend on it")
           ->capture_default_str();
       // Expanded by main() before parsing; declared here so that --help lists it.
       app.add_option("--config", o->config_file,
                      "options from a file of `name: value` lines (a flat YAML subset); "
                      "options on the command line win");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli
