// seqtopo localize: where in a mapped traverse is the robot? The query x map similarity matrix is aligned
// (localize/localize.hpp), or, with --online, the query frames are taken one at a time
// (localize/online_localizer.hpp). Outputs (INTERFACE.md): matches.csv, and with ground truth metrics.json,
// pr_curve.png and report.html.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <variant>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "progress.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/localize_outputs.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/localize_pipeline.hpp"
#include "sequence_options.hpp"

namespace seqtopo::cli::localize_command {
namespace {

namespace fs = std::filesystem;

struct LocalizeOptions {
  std::vector<std::string> map_paths;  // --map, once per map session
  SequenceOptions sequence;
  std::string map_path, query_path, out_dir = "seqtopo-out", input_kind = "auto", metric;
  std::optional<std::string> descriptor;  // default: the map's descriptors (LocalizeSettings)
  std::optional<float> kappa;
  bool kappa_auto = false;
  std::string gt, gt_map_poses;
  std::optional<double> gt_radius;
  std::optional<std::size_t> tolerance;  // default by the ground truth's format (ground_truth.hpp)
  std::size_t every = 1, window = 10, score_window = 10, lag = 0;
  float gap = 2.0F, threshold = 10.0F, offset = 0.75F;
  double min_confidence = localize::LocalizeConfig{}.min_confidence;
  std::optional<float> cap;
  std::optional<std::string> speeds;  // comma-separated; default LocalizeConfig's
  bool online = false, no_reverse = false;
  unsigned threads = 0;
};

// --speeds: numbers separated by commas (each by the one number parser), 1 first (localize::validate_speeds).
std::vector<double> parse_speeds(const std::string& text) {
  std::vector<double> out;
  for (std::size_t from = 0;;) {
    const auto comma = text.find(',', from);
    out.push_back(parse_number<double>("--speeds", text.substr(from, comma - from)));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  try {
    localize::validate_speeds(out);
  } catch (const std::invalid_argument& e) {
    throw InputError("--speeds", e.what());
  }
  return out;
}

// ---- offline ---------------------------------------------------------------------------------------

// The similarity file when one of --map/--query is an N x M similarity.npy (rows = query, columns = map).
std::optional<fs::path> similarity_file(const LocalizeOptions& o, pipeline::InputKind kind) {
  auto is_similarity = [&](const std::string& path) {
    if (path.empty() || path == "-") return false;
    return pipeline::resolve_input_kind({path, kind, o.every}) == pipeline::InputKind::similarity;
  };
  const bool map_s = is_similarity(o.map_path), query_s = is_similarity(o.query_path);
  if (!map_s && !query_s) return std::nullopt;
  if (map_s && query_s && fs::path(o.map_path) != fs::path(o.query_path)) {
    throw InputError("--query", "give the query x map similarity.npy once (as --map or --query), not two of them");
  }
  if (map_s != query_s && !o.map_path.empty() && !o.query_path.empty()) {
    throw InputError(map_s ? "--query" : "--map",
                     "cannot be combined with a similarity matrix; the matrix already holds both sequences");
  }
  return fs::path(map_s ? o.map_path : o.query_path);
}

localize::LocalizeConfig localize_config(const LocalizeOptions& o, std::size_t confidence_tolerance) {
  localize::LocalizeConfig c;
  c.search.gap = o.gap;
  c.search.cap = o.cap;
  c.significance.threshold = o.threshold;
  c.score.contrast_offset = o.offset;
  c.score.contrast_window = o.window;
  c.score_window = o.score_window;
  c.tolerance = confidence_tolerance;
  c.min_confidence = o.min_confidence;
  c.search.reverse = !o.no_reverse;
  c.lag = o.lag;
  if (o.speeds) c.speeds = parse_speeds(*o.speeds);
  c.threads = std::min(2U, resolve_threads(o.threads));
  try {
    localize::validate(c);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const char* option = "--threshold";
    for (const char* name : {"gap", "cap", "contrast_offset"}) {
      if (what.rfind(name, 0) == 0)
        option = name == std::string("gap") ? "--gap" : name == std::string("cap") ? "--cap" : "--contrast-offset";
    }
    throw InputError(option, what);
  }
  return c;
}

void run(LocalizeOptions o) {
  if (!o.map_paths.empty()) o.map_path = o.map_paths.front();
  if (o.map_path.empty() && o.query_path.empty()) throw InputError("--map", "give --map and --query");
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  if (o.every == 0) throw InputError("--every", "must be at least 1");
  // Ground truth is read before the work, so a bad file fails fast.
  std::optional<pipeline::GroundTruthFile> truth_source, map_poses;
  constexpr std::string_view keywords[] = {"same-index"};
  if (!o.gt.empty()) truth_source = pipeline::read_ground_truth(o.gt, keywords, o.gt_radius);
  if (!o.gt_map_poses.empty()) {
    map_poses = pipeline::read_ground_truth(o.gt_map_poses, {}, o.gt_radius, "--gt-map-poses");
    if (!truth_source || truth_source->format != pipeline::GroundTruthFormat::poses) {
      throw InputError("--gt-map-poses", "is the map frames' poses of a poses --ground-truth (the query frames')");
    }
    if (map_poses->format != pipeline::GroundTruthFormat::poses) {
      throw InputError(o.gt_map_poses, "is not a poses file (index,x,y CSV, TUM or KITTI)");
    }
  }
  if (truth_source && truth_source->format == pipeline::GroundTruthFormat::poses && !map_poses) {
    throw InputError("--gt-map-poses",
                     "needed with a poses ground truth: the map frames' poses (the "
                     "--ground-truth file has the query frames')");
  }
  const std::size_t tolerance =
      o.tolerance.value_or(truth_source ? pipeline::default_localization_tolerance(*truth_source) : 2);
  pipeline::LocalizeRequest request;
  // The confidence does not depend on the ground truth given: without --tolerance it is the probability of a
  // guess within the place-recognition window (LocalizeConfig's, as the map's confidence_tolerance).
  request.settings.localize = localize_config(o, o.tolerance.value_or(localize::LocalizeConfig{}.tolerance));
  request.online = o.online;
  if (o.lag > 0 && !o.online) throw InputError("--lag", "is for --online (offline, every frame has the whole query)");
  if (o.speeds && o.online) throw InputError("--speeds", "is offline only (--online searches the query as recorded)");
  const bool have_matrix = [&] {
    for (const auto* p : {&o.map_path, &o.query_path}) {
      if (!p->empty() && *p != "-" && !fs::exists(*p)) throw InputError(*p, "does not exist");
    }
    for (const auto& p : o.map_paths) {
      if (!fs::exists(p)) throw InputError(p, "does not exist");
    }
    return similarity_file(o, kind).has_value();
  }();
  if (!have_matrix && (o.map_path.empty() || o.query_path.empty())) {
    throw InputError(o.map_path.empty() ? "--map" : "--query", "is required unless a similarity.npy is given");
  }
  if (o.query_path == "-" && !o.online) throw InputError("--query", "'-' (paths on standard input) needs --online");
  request.similarity_file = similarity_file(o, kind);
  request.query = {o.query_path, kind, o.every};
  o.sequence.apply(request.query);
  if (o.map_paths.size() > 1 && request.similarity_file) {
    throw InputError("--map", "a similarity matrix holds the whole map; give it once, not with other map sessions");
  }
  for (const auto& p : o.map_paths.size() > 1 ? o.map_paths : std::vector<std::string>{o.map_path}) {
    request.map.push_back({p, kind, o.every});
    o.sequence.apply(request.map.back());
  }
  pipeline::DescriptorOverrides described =
      descriptor_overrides(o.descriptor, o.metric.empty() ? std::nullopt : std::optional(o.metric), o.kappa, o.threads);
  if (request.similarity_file && o.online) {  // rows read from the file, compared by nothing
    described.metric.reset();
    described.kappa.reset();
    described.threads.reset();
  }
  pipeline::apply_descriptor_overrides(described, request.settings.descriptors, request.settings.detect_panoramas,
                                       request.settings.similarity);
  // The report's thumbnails are made while the similarity reads the images (offline, image folders, a map of one
  // session), so that the report need not decode them again. A listing that fails is left to the run to report.
  std::optional<outputs::ThumbnailCollector> query_thumbnails, map_thumbnails;
  const auto images_in = [](const pipeline::SequenceInput& input) -> std::optional<std::size_t> {
    try {
      if (pipeline::resolve_input_kind(input) != pipeline::InputKind::images) return std::nullopt;
      return input.frames.empty() ? pipeline::list_input_images(input).files.size() : input.frames.size();
    } catch (const std::exception&) {
      return std::nullopt;
    }
  };
  if (!o.online && !request.similarity_file && request.map.size() == 1) {
    if (const auto frames = images_in(request.query)) {
      query_thumbnails.emplace(std::vector{*frames});
      request.settings.similarity.on_image = [&](std::size_t i, const RgbImage& image) {
        query_thumbnails->add(i, image);
      };
    }
    if (const auto frames = images_in(request.map.front())) {
      map_thumbnails.emplace(std::vector{*frames});
      request.settings.similarity.on_column_image = [&](std::size_t i, const RgbImage& image) {
        map_thumbnails->add(i, image);
      };
    }
  }
  // Checked (and staged beside) before the work: an output folder that cannot be replaced costs no time.
  std::vector<fs::path> inputs{o.map_path, o.query_path, o.gt_map_poses};
  if (truth_source && truth_source->format != pipeline::GroundTruthFormat::same_index) inputs.emplace_back(o.gt);
  io::OutputDirectory out(o.out_dir, {.inputs = inputs, .command = "seqtopo localize"});

  Progress progress("seqtopo localize");
  progress.plan({"localization", "accuracy and baselines", "files and figures", "report"});
  const double setup_seconds = progress.elapsed();
  // Online, the answers go to stdout frame by frame; the stage lines stay on stderr, without a bar between them.
  if (o.online) progress.pause_bar(true);
  if (o.online) std::cout << "query,map,confidence,latency_ms,wait_ms\n";
  const auto on_frame = [](std::size_t q, const pipeline::FrameAnswer& a, double seconds, double wait) {
    // The decision: the map frame when the frame is in the map, else empty; the confidence either way.
    std::cout << fmt::format("{},{},{:.4g},{:.3f},{:.3f}\n", q,
                             a.in_map && a.map ? std::to_string(*a.map) : std::string(), a.confidence, 1e3 * seconds,
                             1e3 * wait)
              << std::flush;
  };
  request.settings.similarity.progress = [&progress](std::string_view what, std::size_t done, std::size_t total) {
    progress.advance(done, total, what == "matrix" ? "cells of the matrix" : "images described");
  };
  request.settings.similarity.note = [&progress](std::string_view text) { progress.line(text); };
  const auto next_path = []() -> std::optional<std::string> { return read_bounded_line(std::cin, "stdin"); };
  progress.begin("localization");
  pipeline::LocalizeRun r = pipeline::localize_sequences(request, on_frame, next_path);
  const double localization_seconds = progress.end();
  for (const auto& note : r.notes) progress.line("      " + note);

  // The ground truth must fit the sizes before anything is written.
  progress.begin("accuracy and baselines");
  std::optional<evaluation::LocalizationTruth> truth;
  if (truth_source) {
    truth =
        pipeline::localization_truth(*truth_source, r.queries, r.maps, map_poses ? &*map_poses : nullptr, o.gt_radius);
  }
  if (truth) pipeline::evaluate_localization_run(r, *truth, tolerance, resolve_threads(o.threads));
  const double accuracy_seconds = progress.end();
  // The report's timings: the command's setup, the localization's own parts and the rest of its stage.
  double parts = 0;
  for (const auto& t : r.timings) parts += t.second;
  r.timings.insert(r.timings.begin(), {"start-up, options, inputs checked", setup_seconds});
  r.timings.emplace_back("localization: the rest (reading, online frames)",
                         std::max(0.0, localization_seconds - parts));
  r.timings.emplace_back("accuracy and baselines", accuracy_seconds);
  progress.begin("files and figures");
  const std::size_t not_in_map = outputs::write_localize_outputs(r, out);
  r.timings.emplace_back("files and figures", progress.end());
  progress.begin("report");
  const auto report =
      outputs::write_localize_report(r, out,
                                     {.seconds_before = progress.elapsed(),
                                      .command_line = command_line(),
                                      .thumbnails = query_thumbnails ? &query_thumbnails->jpegs() : nullptr,
                                      .column_thumbnails = map_thumbnails ? &map_thumbnails->jpegs() : nullptr});
  progress.end();
  if (!report.warning.empty()) progress.line("warning: " + report.warning);
  out.commit();

  std::string line = fmt::format("seqtopo localize: {} query frames in {} map frames, {} not in the map, {:.2f} s",
                                 r.queries, r.maps, not_in_map, r.seconds);
  if (r.metrics) {
    line += fmt::format("; recall@1 {:.3f}, AUC {:.3f}, R@100P {:.3f} (+-{} frames)", r.metrics->recall_at_1,
                        r.metrics->auc, r.metrics->recall_at_100_precision, tolerance);
  }
  if (o.online) {
    std::vector<double> waits = r.waits;
    std::sort(waits.begin(), waits.end());
    line += fmt::format(
        "; latency per frame (processing) median {:.3f} ms, max {:.3f} ms; waiting for frames "
        "median {:.3f} ms",
        1e3 * outputs::latency_percentile(r, 0.5), 1e3 * outputs::latency_percentile(r, 1.0),
        waits.empty() ? 0.0 : 1e3 * waits[waits.size() / 2]);
  }
  progress.line(line.substr(std::string_view("seqtopo localize: ").size()) + " -> " +
                (out.dir() / "matches.csv").string());
}

const RegisterCommand registered{
    {"localize",
     "Localize a query traverse in a mapped one by aligning image sequences (offline, or --online frame by frame)",
     [](CLI::App& app) {
       auto o = std::make_shared<LocalizeOptions>();
       app.add_option("--map", o->map_paths,
                      "mapped traverse: image folder, video, bag, descriptors.npy, or a query x map similarity.npy "
                      "(rows = query frames, columns = map frames; then --query is not needed); given several "
                      "times, the map is those sessions one after the other")
           ->allow_extra_args(false);
       add_sequence_options(app, o->sequence);
       app.add_option(
           "--query", o->query_path,
           "query traverse of the same kind ('-' with --online: image paths on standard input, one per line)");
       app.add_option("--out", o->out_dir, "output folder")->capture_default_str();
       app.add_option("--input-kind", o->input_kind, "auto|images|video|descriptors|similarity")->capture_default_str();
       add_number(app, "--every", o->every, kAtLeastOne,
                  "keep every K-th frame: of a video or bag, the images of a folder, the rows of descriptors.npy");
       app.add_option("--descriptor", o->descriptor,
                      "joint-histogram|patch|panorama|npy (descriptors.npy inputs use their rows), or several "
                      "comma-separated, fused as the map fuses them (default: joint-histogram,patch; "
                      "joint-histogram,panorama for 360-degree panoramas)");
       app.add_option("--metric", o->metric, "chi2|l1|cosine|sad (default: by descriptor)");
       add_number_or(app, "--kappa", o->kappa, "auto", o->kappa_auto, kPositive,
                     "K > 0 in S = 1 - K * D, or auto (rows are contrast-enhanced, so it rarely matters)");
       add_number(app, "--gap", o->gap, kNonNegative,
                  "gap penalty per skipped frame [score units = standard deviations]");
       add_number(app, "--cap", o->cap, kPositive, "upper bound on the cumulative score (default: none)");
       add_number(app, "--threshold", o->threshold, kAnyFinite,
                  "online: minimum confidence; offline: alignments below this score count as chance when the "
                  "sequence is too short for significance statistics");
       add_number(app, "--min-confidence", o->min_confidence, kProbability,
                  "a frame whose best guess has a lower confidence (the probability it is right) is reported "
                  "not in the map");
       add_number(app, "--contrast-offset,--offset", o->offset, kAnyFinite,
                  "subtracted from the contrast-enhanced similarity [standard deviations] (--offset: old name)");
       add_number(app, "--contrast-window,--window", o->window, kNonNegative,
                  "contrast enhancement: +-W map frames (0 = whole row; --window: old name)");
       add_number(app, "--score-window", o->score_window, kNonNegative,
                  "per-frame score: +-W query frames of the alignment");
       app.add_flag("--no-reverse", o->no_reverse, "do not search the map driven backwards");
       app.add_option("--speeds", o->speeds,
                      "offline: the query's speeds against the map searched, map frames per query frame, 1 first "
                      "(default 1,1.5,2,0.667,0.5: as recorded, then the others where that leaves frames unsure)");
       app.add_option("--ground-truth,--gt", o->gt,
                      "ground truth: same-index (query k is map k), a query x map image or .npy matrix, a pairs CSV "
                      "(query,map), VPR-Bench's ground_truth_new.npy, or the query frames' poses (index,x,y CSV, "
                      "TUM, KITTI) with --gt-map-poses and --gt-radius (INTERFACE.md); also scores the single-frame "
                      "and SeqSLAM baselines on the same matrix");
       app.add_option("--gt-map-poses", o->gt_map_poses, "the map frames' poses, with a poses --ground-truth");
       add_number(app, "--gt-radius", o->gt_radius, kPositive,
                  "same place when closer than this [m] (poses ground truth)");
       add_number(app, "--tolerance", o->tolerance, kNonNegative,
                  "a match within +-T map frames of a true one is correct (default 2 with same-index, 0 with a "
                  "file, which lists the true frames themselves); the confidence is the probability of a match "
                  "within +-T (without --tolerance, +-2, whatever the ground truth)");
       app.add_flag("--online", o->online, "take query frames one at a time; print the best map frame after each");
       add_number(app, "--lag", o->lag, {.min = 0, .max = localize::kMaxLag},
                  "online: answer each frame once this many later frames have arrived, with their evidence "
                  "(fixed-lag smoothing; 0 = at once)");
       add_number(app, "--threads", o->threads, kThreads,
                  "worker threads (0 = all cores; more than the cores are not used)");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::localize_command
