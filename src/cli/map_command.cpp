// seqtopo map: the main job (INTERFACE.md). Sequence -> similarity -> forward and reverse alignments ->
// pruning -> labels -> topological map -> metric picture -> figures, metrics and report.
#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command_registry.hpp"
#include "map_online.hpp"
#include "options/number_options.hpp"
#include "progress.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/outputs/report_options.hpp"
#include "seqtopo/pipeline/machine_memory.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/similarity/memory.hpp"
#include "sequence_options.hpp"

namespace seqtopo::cli::map_command {
namespace {

namespace fs = std::filesystem;

// The bundled corridor, the default input: found from this program's own place first, so that an installed copy
// uses its own data wherever it was installed or moved to (PREFIX/libexec/seqtopo/seqtopo-main ->
// PREFIX/share/seqtopo; a Python wheel's seqtopo/bin/seqtopo-main -> seqtopo/data), then the source tree of a
// build folder, then the prefix configured at build time; else the relative path, which names the missing folder.
fs::path bundled_corridor() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) {
    candidates.push_back(self.parent_path() / ".." / ".." / "share" / "seqtopo" / "rtabmap-corridor");
    candidates.push_back(self.parent_path() / ".." / "data" / "rtabmap-corridor");
  }
  candidates.push_back(fs::path(SEQTOPO_DATA_DIR) / "rtabmap-corridor");
  candidates.push_back(fs::path(SEQTOPO_INSTALLED_DATA_DIR) / "rtabmap-corridor");
  for (const auto& candidate : candidates) {
    if (fs::is_directory(candidate, ec)) return candidate.lexically_normal();
  }
  return "data/rtabmap-corridor";
}

struct MapOptions {
  std::vector<std::string> inputs;  // one per session
  SequenceOptions sequence;
  std::vector<std::string> odometry_files, times_files;
  std::string odometry_topic;
  std::optional<double> every_metres;
  std::string out = "seqtopo-out";
  std::string input_kind = "auto";
  std::size_t every = 1;
  std::string preset = "default";
  // The changes to the preset's settings given as numbers or flags; the named ones below are parsed into it.
  pipeline::MapOverrides set;
  std::optional<std::string> descriptor, metric_name, alignment_set, odometry_gate;
  bool kappa_auto = false, fpp_auto = false, no_reverse = false;
  std::optional<std::string> engine;  // default automatic
  bool streaming = false, sparse = false;
  pipeline::SparseOptions sparse_options;
  std::string ground_truth, gt_places, gt_poses;
  std::optional<double> gt_radius;
  unsigned threads = 0;
  std::string config_file;
  bool online = false, no_offline_outputs = false, no_candidates = false;
  std::optional<double> candidate_e_value;
  std::string save_matrices = "auto";
  std::string images;  // the images of a descriptors.npy / similarity.npy input, for the report
};

// --odometry-gate BASE,DRIFT[,WINDOW[,TURN]] or none; InputError naming the option otherwise.
std::optional<mapping::OdometryGate> parse_odometry_gate(const std::string& text) {
  if (text == "none") return std::nullopt;
  std::vector<std::string> fields;
  for (std::size_t from = 0;;) {
    const auto comma = text.find(',', from);
    fields.push_back(text.substr(from, comma - from));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  if (fields.size() < 2 || fields.size() > 4) {
    throw InputError("--odometry-gate",
                     "expected BASE,DRIFT[,WINDOW[,TURN]] (metres, metres per metre travelled, metres, radians "
                     "per metre travelled; all >= 0) or none, got '" +
                         text + "'");
  }
  mapping::OdometryGate gate;
  gate.base = parse_number<double>("--odometry-gate", fields[0], kNonNegative);
  gate.drift = parse_number<double>("--odometry-gate", fields[1], kNonNegative);
  if (fields.size() >= 3) gate.trim_window = parse_number<double>("--odometry-gate", fields[2], kNonNegative);
  if (fields.size() == 4) gate.turn = parse_number<double>("--odometry-gate", fields[3], kNonNegative);
  return gate;
}

// The changes to the preset the options ask for, the named ones parsed (pipeline::apply_overrides applies them;
// --online reads its part of them).
pipeline::MapOverrides map_overrides(const MapOptions& o) {
  pipeline::MapOverrides set = o.set;
  set.described = descriptor_overrides(o.descriptor, o.metric_name, o.set.described.kappa, o.threads);
  if (o.alignment_set) {
    try {
      set.alignment_set = align::parse_alignment_set(*o.alignment_set);
    } catch (const std::invalid_argument&) {
      throw InputError("--alignment-set",
                       "expected locally-optimal or non-intersecting, got '" + *o.alignment_set + "'");
    }
  }
  if (o.odometry_gate) {
    // A bad value is a bad command line (exit 2), as for every other number option.
    try {
      set.odometry_gate = parse_odometry_gate(*o.odometry_gate);
      set.no_odometry_gate = !set.odometry_gate;
    } catch (const InputError& e) {
      throw CLI::ValidationError(e.subject(), e.what());
    }
  }
  if (o.no_reverse) set.reverse = false;
  return set;
}

// The options of the offline map that --online does not read (its offline outputs too are the online run's
// defaults): given with --online they would be ignored without a word, so they are refused.
std::vector<std::string> ignored_online(const MapOptions& o) {
  std::vector<std::string> given;
  const auto check = [&](bool set, const char* name) {
    if (set) given.emplace_back(name);
  };
  check(!o.odometry_files.empty(), "--odometry");
  check(!o.times_files.empty(), "--times");
  check(!o.odometry_topic.empty(), "--odometry-topic");
  check(o.every_metres.has_value(), "--every-metres");
  check(o.preset != "default", "--preset");
  check(o.descriptor.has_value(), "--descriptor");
  check(o.metric_name.has_value(), "--metric");
  check(o.set.described.kappa || o.kappa_auto, "--kappa");
  check(o.fpp_auto, "--frames-per-place auto");
  check(o.set.cap_factor.has_value(), "--cap-factor");
  check(o.odometry_gate.has_value(), "--odometry-gate");
  check(o.set.odometry_evidence.has_value(), "--odometry-evidence");
  check(o.engine.has_value(), "--engine");
  check(o.alignment_set.has_value(), "--alignment-set");
  check(o.set.graph_cleanup.has_value(), "--graph-cleanup");
  check(o.streaming, "--streaming");
  check(o.sparse, "--sparse");
  check(o.sparse_options.neighbours.has_value(), "--neighbours");
  check(o.sparse_options.diagonal_reach.has_value(), "--diagonal-reach");
  check(!o.gt_places.empty(), "--gt-places");
  check(!o.gt_poses.empty(), "--gt-poses");
  check(!o.sequence.image_topic.empty(), "--image-topic");
  check(o.sequence.recursive, "--recursive");
  check(o.sequence.skip_unreadable, "--skip-unreadable");
  check(o.save_matrices != "auto", "--save-matrices");
  check(!o.images.empty(), "--images");
  return given;
}

void run(MapOptions o) {
  // An option that would be ignored without a word is refused.
  if (o.gt_radius && o.ground_truth.empty()) {
    throw InputError("--gt-radius", "is the same-place radius of a poses.csv ground truth: give --ground-truth too");
  }
  if (o.online) {
    if (const auto ignored = ignored_online(o); !ignored.empty()) {
      throw InputError("--online", fmt::format("does not take {} (the offline map's option{}; map without --online "
                                               "to use {})",
                                               fmt::join(ignored, ", "), ignored.size() > 1 ? "s" : "",
                                               ignored.size() > 1 ? "them" : "it"));
    }
    run_map_online({.inputs = o.inputs,
                    .out = o.out,
                    .input_kind = o.input_kind,
                    .ground_truth = o.ground_truth,
                    .gt_radius = o.gt_radius,
                    .every = o.every,
                    .set = map_overrides(o),
                    .candidate_e_value = o.candidate_e_value,
                    .no_candidates = o.no_candidates,
                    .offline_outputs = !o.no_offline_outputs,
                    .threads = o.threads});
    return;
  }
  const auto matrices = option_value("--save-matrices", [&]() -> std::optional<bool> {
    if (o.save_matrices == "auto") return std::nullopt;
    if (o.save_matrices == "yes") return true;
    if (o.save_matrices == "no") return false;
    throw std::invalid_argument("expected auto, yes or no, got '" + o.save_matrices + "'");
  });
  Progress progress("seqtopo map");
  // Everything the user gave is checked before the long computation starts (and before any progress
  // output), so a mistake costs one line and no time.
  pipeline::MapRequest request;
  // The preset fixes the defaults; every explicit option overrides them.
  const pipeline::MapOverrides overrides = map_overrides(o);
  request.settings =
      pipeline::apply_overrides(option_value("--preset", [&] { return pipeline::map_preset(o.preset); }), overrides);
  request.preset = o.preset;
  request.engine = pipeline::engine_with_flags(
      o.engine ? std::optional(option_value("--engine", [&] { return pipeline::parse_engine(*o.engine); }))
               : std::nullopt,
      o.streaming, o.sparse);
  request.sparse = o.sparse_options;
  const bool streams = pipeline::streams(request.engine);
  const bool bundled_default = o.inputs.empty();
  if (bundled_default) {
    o.inputs = {bundled_corridor().string()};
    // Its ground truth is an N x N image, which the streaming engines refuse.
    if (o.ground_truth.empty() && !streams) o.ground_truth = (fs::path(o.inputs[0]) / "ground_truth.bmp").string();
  }
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  // --odometry and --times: one for a single input, one per session or none for several.
  for (const auto& [name, files] : {std::pair{"--odometry", &o.odometry_files}, std::pair{"--times", &o.times_files}}) {
    if (files->size() > 1 && files->size() != o.inputs.size()) {
      throw InputError(name, fmt::format("given {} times for {} inputs: give it once per session, in the order of "
                                         "the inputs",
                                         files->size(), o.inputs.size()));
    }
    if (files->size() == 1 && o.inputs.size() > 1) {
      throw InputError(name, fmt::format("given once for {} sessions: give it once per session, in the order of the "
                                         "inputs",
                                         o.inputs.size()));
    }
  }
  std::vector<pipeline::SessionSource> sessions;
  for (std::size_t k = 0; k < o.inputs.size(); ++k) {
    pipeline::SessionSource session;
    session.input = {o.inputs[k], kind, o.every};
    o.sequence.apply(session.input);
    if (!o.odometry_files.empty()) session.odometry = o.odometry_files[k];
    if (!o.times_files.empty()) session.times = o.times_files[k];
    session.odometry_topic = o.odometry_topic;
    session.every_metres = o.every_metres;
    sessions.push_back(std::move(session));
  }
  request.sessions = std::move(sessions);
  request.truth = {o.ground_truth, o.gt_radius, o.gt_places, o.gt_poses};
  request.report_images = o.images;
  const pipeline::MapJob job(request);
  std::vector<std::filesystem::path> inputs(o.inputs.begin(), o.inputs.end());
  for (const auto* files : {&o.odometry_files, &o.times_files})
    inputs.insert(inputs.end(), files->begin(), files->end());
  for (const auto* file : {&o.ground_truth, &o.gt_places, &o.gt_poses}) inputs.emplace_back(*file);
  io::OutputDirectory out(o.out, {.inputs = inputs, .command = "seqtopo map"});
  if (bundled_default) progress.line("no input given: mapping the bundled corridor data " + o.inputs[0]);
  if (bundled_default && streams) {
    progress.line("its ground truth is an N x N image, which the streaming engines do not read");
  }
  const double setup_seconds = progress.elapsed();
  const auto line = [&progress](std::string_view text) { progress.line(text); };
  // The report's thumbnails are made while the similarity stage reads the images (image folders).
  std::optional<outputs::ThumbnailCollector> thumbnails;
  if (job.input_kind() == pipeline::InputKind::images) {
    std::vector<std::size_t> frames;
    for (const auto& session : job.sessions()) {
      if (session.frames) frames.push_back(*session.frames);
    }
    if (frames.size() == job.sessions().size()) thumbnails.emplace(frames);
  }
  pipeline::MapObserver observer{
      .progress = line, .stage = progress.observer(), .later_stages = {"files and figures", "report"}};
  if (thumbnails)
    observer.on_image = [&thumbnails](std::size_t i, const RgbImage& image) { thumbnails->add(i, image); };
  pipeline::MapRun run = job.run(observer);
  run.timings.insert(run.timings.begin(), {"start-up, options, inputs checked", setup_seconds});

  // The pairs are known now: outputs that would not fit are refused before any is written.
  pipeline::check_outputs_memory(run, pipeline::available_memory_bytes(), o.out);
  progress.begin("files and figures");
  const std::size_t images = run.result.map.labels.size();
  if (!run.streamed() && !matrices && !outputs::writes_matrices(images, matrices)) {
    progress.line(fmt::format(
        "similarity.npy and scores.npy not written: {} images, 2 x {:.0f} MB (written up to {} "
        "images; --save-matrices yes writes them)",
        images, 4e-6 * static_cast<double>(images) * static_cast<double>(images), outputs::kMaxAutoMatrixImages));
  }
  outputs::write_map_outputs(run, out, {.matrices = matrices});
  run.timings.emplace_back("files and figures", progress.end());
  progress.begin("report");
  // The report's timings add up to the wall time up to its own writing (the rest is the final rename).
  const auto report = outputs::write_map_report(run, out,
                                                {.seconds_before = progress.elapsed(),
                                                 .command_line = command_line(),
                                                 .thumbnails = thumbnails ? &thumbnails->jpegs() : nullptr});
  progress.end();
  if (!report.warning.empty()) progress.line("warning: " + report.warning);
  const auto written = out.commit();
  progress.line(fmt::format("wrote {} files to {} in {:.2f} s", written.size(), o.out, progress.elapsed()));
  if (run.metrics) {
    progress.line(fmt::format("loop closures: precision {:.3f} recall {:.3f} F1 {:.3f} AUC {:.3f} R@100P {:.3f}",
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
       app.add_option("input", o->inputs,
                      "image folder, video, bag (.bag, .db3, .mcap), descriptors.npy or similarity.npy; several are "
                      "sessions mapped together (no transition between one's end and the next one's start)");
       app.add_option("--out", o->out, "output folder")->capture_default_str();
       app.add_option("--input-kind", o->input_kind, "auto|images|video|descriptors|similarity")->capture_default_str();
       add_number(app, "--every", o->every, kAtLeastOne,
                  "keep every K-th frame: of a video or bag, the images of a folder, the rows of descriptors.npy "
                  "(odometry and times files list every frame and are thinned alike; a ground truth lists the frames "
                  "kept)");
       app.add_option("--preset", o->preset, "paper (joint histogram, chi2, EKF) or default")->capture_default_str();
       app.add_option("--descriptor", o->descriptor,
                      "joint-histogram|patch|panorama|npy (npy: the rows of a descriptors.npy INPUT), or several "
                      "separated by commas to fuse them (default joint-histogram,patch; paper preset joint-histogram)");
       app.add_option("--metric", o->metric_name, "chi2|l1|cosine|sad (default: by descriptor)");
       add_number_or(app, "--kappa", o->set.described.kappa, "auto", o->kappa_auto, kPositive,
                     "S = 1 - kappa * D: a number > 0, or auto (from the sequence's own distances)");
       add_number(app, "--gap", o->set.gap, kNonNegative,
                  fmt::format("penalty per skipped image (default {})", mapping::MapConfig{}.search.gap));
       app.add_option("--engine", o->engine,
                      "automatic (chosen by the memory the run needs, said on stderr), exact (scalar reference, N x N "
                      "table), fast (vectorized, no N x N table, scores quantized to 1/512), streaming or sparse (as "
                      "--streaming, --sparse); default automatic");
       app.add_option("--alignment-set", o->alignment_set,
                      fmt::format("non-intersecting (Waterman-Eggert: no two revisits share a pair) or locally-optimal "
                                  "(every alignment no shortening or extension improves, after Schmidt; "
                                  "docs/alignment_sets.md); default {}",
                                  align::to_string(mapping::MapConfig{}.alignment_set)));
       app.add_flag(
           "--streaming", o->streaming,
           "--engine streaming: never hold the N x N matrix: contrast-enhanced cosine scores of one vector descriptor "
           "(descriptors.npy rows, or images' patch or panorama thumbnails, by cosine) computed on the fly, "
           "fast engine; "
           "no scores.npy, similarity.npy nor SeqSLAM baseline, similarity.png a block-max overview");
       app.add_flag("--sparse", o->sparse,
                    "--engine sparse: as --streaming, but align only each frame's nearest neighbours (FAISS "
                    "candidates; every other "
                    "pair scores -1): maps of 10^6 frames in a few GB, the same map where the candidates cover "
                    "the revisits (docs/scaling.md)");
       add_number(app, "--neighbours", o->sparse_options.neighbours, kAtLeastOne,
                  "--sparse: candidates per frame (default 10), nearest first");
       add_number(app, "--diagonal-reach", o->sparse_options.diagonal_reach, kNonNegative,
                  fmt::format("--sparse: the diagonals this many frames around each candidate pair are candidates "
                              "too, so a revisit whose frames seldom have their true match among the nearest grows "
                              "from a few (default {})",
                              0));
       app.add_option(
           "--odometry-gate", o->odometry_gate,
           fmt::format("with --odometry: drop alignments whose images odometry puts more than BASE + DRIFT * "
                       "(metres travelled between them) apart, or whose two traversals odometry turns against each "
                       "other by more than a right angle + TURN * (metres travelled between them), and trim an "
                       "alignment's ends where the shapes of its two traversals over WINDOW metres part by more "
                       "than 3 times their scatter in its middle (1 m to BASE; WINDOW 0: no trimming), as "
                       "BASE,DRIFT[,WINDOW[,TURN]], or none (default {},{},{},{})",
                       mapping::OdometryGate{}.base, mapping::OdometryGate{}.drift, mapping::OdometryGate{}.trim_window,
                       mapping::OdometryGate{}.turn));
       add_number_or(app, "--e-value", o->set.e_value, "none", o->set.no_e_value, kPositive,
                     fmt::format("a revisit's E-value (alignments this good expected by chance in this sequence) is "
                                 "at most this, or none for the fixed --threshold (default {}, paper preset none)",
                                 *mapping::MapConfig{}.significance.max_e_value));
       add_number_or(app, "--frames-per-place", o->set.frames_per_place, "auto", o->fpp_auto, kAtLeastOne,
                     "images per place, the unit of --contrast-window and --min-separation; auto estimates it from "
                     "the similarity's decay along the sequence (default auto; paper preset: frames)");
       add_number_or(
           app, "--cap", o->set.cap, "none", o->set.no_cap, kPositive,
           fmt::format("cap on the cumulative score, or none (default: {} x the score a significant alignment "
                       "needs; {} without --e-value)",
                       mapping::MapConfig{}.cap_factor, *mapping::MapConfig{}.search.cap));
       add_number(app, "--cap-factor", o->set.cap_factor, kPositive,
                  fmt::format("without --cap: the cap is this many times the score a significant alignment needs "
                              "(default {})",
                              mapping::MapConfig{}.cap_factor));
       add_number(app, "--threshold", o->set.threshold, kPositive,
                  fmt::format("minimum alignment score of a revisit with --e-value none (default {})",
                              mapping::MapConfig{}.significance.threshold));
       add_number(app, "--min-separation", o->set.min_separation, kSeparation,
                  fmt::format("places (frames with the paper preset) around the diagonal that never count (default {})",
                              mapping::MapConfig{}.search.min_separation));
       add_number(
           app, "--contrast-window", o->set.contrast_window, kNonNegative,
           fmt::format("local contrast enhancement before alignment, half-width in places (paper: frames); 0 = off "
                       "(default {}, paper preset 0)",
                       mapping::MapConfig{}.score.contrast_window));
       add_number(app, "--contrast-offset", o->set.contrast_offset, kAnyFinite,
                  fmt::format("enhanced scores above this many standard deviations are rewarded (default {})",
                              mapping::MapConfig{}.score.contrast_offset));
       app.add_flag("--no-reverse", o->no_reverse, "do not look for paths revisited in the opposite direction");
       app.add_option("--odometry-evidence", o->set.odometry_evidence,
                      "count an alignment's agreement with the odometry as evidence: its E-value times the share of "
                      "chance alignments that agree (INTERFACE.md); true by default")
           ->type_name("true|false");
       app.add_option("--graph-cleanup", o->set.graph_cleanup,
                      "clean the place graph before reading the topology: overhangs, tips, bubbles, redundant edges "
                      "(mapping/graph_cleanup.hpp); true by default, false with --preset paper")
           ->type_name("true|false");
       app.add_option("--odometry", o->odometry_files,
                      "odometry: CSV index,x,y,theta (cumulative) or index,dx,dy,dtheta, CSV timestamp,x,y,yaw, "
                      "TUM or KITTI poses; with several inputs, once per session")
           ->allow_extra_args(false);
       app.add_option("--times", o->times_files,
                      "image times, for a timestamped --odometry and to find session breaks (a long gap where the "
                      "images either side are unlike): times.txt, one time per image [s] (default: times.txt in the "
                      "folder, or numeric file names); with several inputs, once per session")
           ->allow_extra_args(false);
       app.add_option("--odometry-topic", o->odometry_topic,
                      "bags: the nav_msgs/Odometry or PoseStamped topic matched to the images by time (default: "
                      "the bag's only one; none = ignore the bag's odometry)");
       add_number(app, "--every-metres", o->every_metres, kPositive,
                  "keep one frame per this many metres of odometry travelled (needs odometry) [m]");
       add_sequence_options(app, o->sequence);
       add_online_options(app, o->online, o->no_offline_outputs, o->candidate_e_value, o->no_candidates);
       app.add_option("--images", o->images,
                      "with a descriptors.npy or similarity.npy INPUT: the folder of its images, one per row (thinned "
                      "by --every alike), shown in the report");
       app.add_option("--save-matrices", o->save_matrices,
                      fmt::format("write similarity.npy and scores.npy (N x N float32 each): auto (up to {} images, "
                                  "said on stderr when skipped), yes or no",
                                  outputs::kMaxAutoMatrixImages))
           ->capture_default_str();
       app.add_option("--ground-truth,--gt", o->ground_truth,
                      "same-place ground truth: an N x N image or .npy matrix, a pairs CSV (query,map), VPR-Bench's "
                      "ground_truth_new.npy, or poses (index,x,y CSV, TUM, KITTI) with --gt-radius (INTERFACE.md)");
       add_number(app, "--gt-radius", o->gt_radius, kPositive,
                  "same place when closer than this [m] (poses ground truth)");
       app.add_option("--gt-places", o->gt_places, "places.csv (index,place) for topological scores");
       app.add_option("--gt-poses", o->gt_poses,
                      "poses.csv (index,x,y[,theta]) for the metric error (with --odometry)");
       add_number(app, "--threads", o->threads, kThreads,
                  "worker threads (0 = all cores; more than the cores are not used); results do not depend on it");
       // Expanded by main() before parsing; declared here so that --help lists it.
       app.add_option("--config", o->config_file,
                      "options from a file of `name: value` lines (a flat YAML subset); "
                      "options on the command line win");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::map_command
