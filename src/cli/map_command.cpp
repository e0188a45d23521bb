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
#include "number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/similarity/memory.hpp"

namespace seqtopo::cli {
namespace {
namespace fs = std::filesystem;

struct MapOptions {
  std::string input;
  std::string out = "seqtopo-out";
  std::string input_kind = "auto";
  std::size_t every = 1;
  std::string preset = "default";
  std::optional<std::string> descriptor, metric_name;
  std::optional<float> kappa, gap, threshold, cap;
  bool kappa_auto = false, no_cap = false;
  std::optional<std::string> odometry_gate;
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

using Settings = pipeline::MapSettings;

// The preset fixes the defaults; every explicit option overrides them.
Settings resolve_settings(const MapOptions& o) {
  Settings s = option_value("--preset", [&] { return pipeline::map_preset(o.preset); });
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
  if (o.kappa) s.similarity.kappa = *o.kappa;
  s.similarity.threads = resolve_threads(o.threads);
  s.similarity.note = [](std::string_view text) { std::cerr << "seqtopo map: " << text << "\n"; };
  if (o.gap) s.map.gap = *o.gap;
  if (o.threshold) s.map.threshold = *o.threshold;
  if (o.no_cap) s.map.cap.reset();
  if (o.cap) s.map.cap = *o.cap;
  const std::string engine = o.engine.value_or(o.streaming ? "fast" : "exact");
  if (engine == "fast") {
    s.map.engine = mapping::MapConfig::Engine::fast;
  } else if (engine != "exact") {
    throw InputError("--engine", "expected exact or fast, got '" + engine + "'");
  }
  if (o.odometry_gate) {
    if (*o.odometry_gate == "none") {
      s.map.odometry_gate.reset();
    } else {
      const auto comma = o.odometry_gate->find(',');
      if (comma == std::string::npos) {
        throw InputError("--odometry-gate",
                         "expected BASE,DRIFT (metres, metres per metre travelled, both >= 0) or "
                         "none, got '" +
                             *o.odometry_gate + "'");
      }
      mapping::OdometryGate gate;
      gate.base = parse_number<double>("--odometry-gate", o.odometry_gate->substr(0, comma), kNonNegative);
      gate.drift = parse_number<double>("--odometry-gate", o.odometry_gate->substr(comma + 1), kNonNegative);
      s.map.odometry_gate = gate;
    }
  }
  if (o.min_separation) s.map.min_separation = *o.min_separation;
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
  if (o.kappa || o.kappa_auto)
    throw InputError("--kappa", "has no effect with --streaming: the contrast enhancement removes kappa");
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

void run(MapOptions o) {
  const auto total_start = std::chrono::steady_clock::now();
  // Everything the user gave is checked before the long computation starts (and before any progress
  // output), so a mistake costs one line and no time.
  pipeline::MapRequest request;
  request.settings = resolve_settings(o);
  request.preset = o.preset;
  const bool bundled_default = o.input.empty();
  if (bundled_default) {
    const fs::path bundled = fs::path(SEQTOPO_DATA_DIR) / "rtabmap-corridor";
    o.input = fs::exists(bundled) ? bundled.string() : "data/rtabmap-corridor";
    // Its ground truth is an N x N image, which --streaming refuses.
    if (o.ground_truth.empty() && !o.streaming) o.ground_truth = (fs::path(o.input) / "ground_truth.bmp").string();
  }
  request.input = {o.input, option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); }),
                   o.every};
  request.odometry = o.odometry;
  request.truth = {o.ground_truth, o.gt_radius, o.gt_places, o.gt_poses};
  request.streaming = o.streaming;
  const pipeline::MapJob job(request);
  if (o.streaming) check_streaming(o, request.settings, job.input_kind());
  io::OutputDirectory out(
      o.out, {.inputs = {o.input, o.odometry, o.ground_truth, o.gt_places, o.gt_poses}, .command = "seqtopo map"});
  if (bundled_default) progress("no input given: mapping the bundled corridor data " + o.input);
  if (bundled_default && o.streaming) progress("its ground truth is an N x N image, which --streaming does not read");
  pipeline::MapRun run = job.run({.progress = [](std::string_view text) { progress(std::string(text)); }});

  // The pairs are known now: outputs that would not fit are refused before any is written.
  pipeline::check_outputs_memory(run, similarity::available_memory_bytes(), o.out);
  const auto t = std::chrono::steady_clock::now();
  outputs::write_map_outputs(run, out);
  run.timings.emplace_back("figures and report", seconds_since(t));
  outputs::write_map_report(run, out);
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
       add_number(app, "--every", o->every, kAtLeastOne, "video: use every K-th frame");
       app.add_option("--preset", o->preset, "paper (joint histogram, chi2, EKF) or default")->capture_default_str();
       app.add_option("--descriptor", o->descriptor,
                      "joint-histogram|patch|panorama, or several separated by commas to fuse them "
                      "(default joint-histogram,patch; paper preset joint-histogram)");
       app.add_option("--metric", o->metric_name, "chi2|l1|cosine|sad (default: by descriptor)");
       add_number_or(app, "--kappa", o->kappa, "auto", o->kappa_auto, kPositive,
                     "S = 1 - kappa * D: a number > 0, or auto (from the sequence's own distances)");
       add_number(app, "--gap", o->gap, kNonNegative,
                  fmt::format("penalty per skipped image (default {})", mapping::MapConfig{}.gap));
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
       add_number_or(app, "--cap", o->cap, "none", o->no_cap, kPositive,
                     fmt::format("cap on the cumulative score, or none (default {})", *mapping::MapConfig{}.cap));
       add_number(app, "--threshold", o->threshold, kPositive,
                  fmt::format("minimum alignment score of a revisit (default {})", mapping::MapConfig{}.threshold));
       add_number(app, "--min-separation", o->min_separation, kAtLeastOne,
                  fmt::format("frames around the diagonal that never count (default {})",
                              mapping::MapConfig{}.min_separation));
       add_number(app, "--contrast-window", o->contrast_window, kNonNegative,
                  fmt::format("local contrast enhancement before alignment, half-width in frames; 0 = off "
                              "(default {}, paper preset 0)",
                              mapping::MapConfig{}.contrast_window));
       add_number(app, "--contrast-offset", o->contrast_offset, kAnyFinite,
                  fmt::format("enhanced scores above this many standard deviations are rewarded (default {})",
                              mapping::MapConfig{}.contrast_offset));
       app.add_flag("--no-reverse", o->no_reverse, "do not look for paths revisited in the opposite direction");
       app.add_option("--odometry", o->odometry, "odometry CSV: index,x,y,theta (cumulative) or index,dx,dy,dtheta");
       app.add_option("--ground-truth", o->ground_truth, "N x N same-place image, or poses.csv with --gt-radius");
       add_number(app, "--gt-radius", o->gt_radius, kPositive,
                  "same place when closer than this [m] (poses.csv ground truth)");
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
}  // namespace seqtopo::cli
