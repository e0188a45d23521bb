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
#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/localize/online_localizer.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/plot/pr_curve.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct LocalizeOptions {
  std::string map_path, query_path, out_dir = "seqtopo-out", input_kind = "auto", descriptor = "patch", metric, kappa;
  std::string gt;
  std::size_t tolerance = 2, every = 1, window = 10, score_window = 10;
  float gap = 2.0F, threshold = 10.0F, offset = 0.75F;
  std::optional<float> cap;
  bool online = false, no_reverse = false;
  unsigned threads = 0;
};

// One query frame's answer, whichever mode produced it.
struct Answer {
  std::optional<std::size_t> map;
  float score = 0;
  std::vector<std::size_t> candidates;
};

struct Run {
  SimilarityMatrix similarity;  // query x map (offline, or the rows seen online when they were kept)
  std::size_t queries = 0, maps = 0;
  std::vector<Answer> answers;
  std::vector<align::LocalAlignment> alignments;
  std::vector<double> latencies;  // [s] per frame, online
  std::vector<std::pair<std::string, double>> timings;
};

// ---- offline ---------------------------------------------------------------------------------------

pipeline::SimilarityConfig similarity_config(const LocalizeOptions& o) {
  pipeline::SimilarityConfig c;
  c.descriptor = option_value("--descriptor", [&] { return pipeline::parse_descriptor(o.descriptor); });
  if (!o.metric.empty()) c.distance = option_value("--metric", [&] { return similarity::parse_distance(o.metric); });
  if (!o.kappa.empty() && o.kappa != "auto") {
    c.kappa = option_value("--kappa", [&] {
      std::size_t used = 0;
      const float k = std::stof(o.kappa, &used);
      if (used != o.kappa.size() || !(k > 0) || !std::isfinite(k))
        throw std::invalid_argument("expected a number > 0 or auto");
      return k;
    });
  }
  c.threads = resolve_threads(o.threads);
  return c;
}

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

localize::LocalizeConfig localize_config(const LocalizeOptions& o) {
  localize::LocalizeConfig c;
  c.gap = o.gap;
  c.cap = o.cap;
  c.threshold = o.threshold;
  c.offset = o.offset;
  c.enhancement_window = o.window;
  c.score_window = o.score_window;
  c.reverse = !o.no_reverse;
  c.threads = std::min(2U, resolve_threads(o.threads));
  try {
    localize::validate(c);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const char* option = "--threshold";
    for (const char* name : {"gap", "cap", "offset"}) {
      if (what.rfind(name, 0) == 0)
        option = name == std::string("gap") ? "--gap" : name == std::string("cap") ? "--cap" : "--offset";
    }
    throw InputError(option, what);
  }
  return c;
}

Answer answer_of(const localize::FrameMatch& f) {
  Answer a;
  if (f.covered) a.map = f.map;
  a.score = f.score;
  a.candidates = f.candidates;
  return a;
}

void run_offline(const LocalizeOptions& o, const localize::LocalizeConfig& config, pipeline::InputKind kind, Run& run) {
  const auto t0 = Clock::now();
  pipeline::SimilarityResult s;
  try {
    if (const auto file = similarity_file(o, kind)) {
      s = pipeline::compute_similarity(pipeline::SequenceInput{*file, pipeline::InputKind::similarity, 1},
                                       pipeline::SequenceInput{*file, pipeline::InputKind::similarity, 1},
                                       similarity_config(o));
    } else {
      s = pipeline::compute_similarity(pipeline::SequenceInput{o.query_path, kind, o.every},
                                       pipeline::SequenceInput{o.map_path, kind, o.every}, similarity_config(o));
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(o.query_path.empty() ? o.map_path : o.query_path, e.what());
  }
  run.timings.emplace_back("similarity matrix", seconds_since(t0));
  run.similarity = std::move(s.similarity);
  run.queries = run.similarity.rows;
  run.maps = run.similarity.cols;

  const auto t1 = Clock::now();
  const auto result = localize::localize_sequence(run.similarity, config);
  run.timings.emplace_back("alignment (forward and reverse)", seconds_since(t1));
  run.alignments = result.alignments;
  for (const auto& f : result.frames) run.answers.push_back(answer_of(f));
}

// ---- online ------------------------------------------------------------------------------------------

// A descriptor of one frame: dense (thumbnail, external descriptor) or a sparse joint histogram.
using FrameDescriptor = std::variant<std::vector<float>, similarity::SparseHistogram>;

struct Describer {
  pipeline::Descriptor descriptor;
  pipeline::SimilarityConfig config;
  FrameDescriptor operator()(const RgbImage& image) const {
    if (descriptor == pipeline::Descriptor::joint_histogram)
      return image::joint_histogram(image, config.joint_histogram);
    return pipeline::dense_descriptor(image, descriptor, config);
  }
};

double frame_distance(similarity::Distance metric, const FrameDescriptor& a, const FrameDescriptor& b) {
  if (a.index() != b.index()) throw std::invalid_argument("both sequences must have the same kind of descriptor");
  if (const auto* x = std::get_if<std::vector<float>>(&a))
    return similarity::distance(metric, *x, std::get<std::vector<float>>(b));
  return similarity::distance(metric, std::get<similarity::SparseHistogram>(a),
                              std::get<similarity::SparseHistogram>(b));
}

// Calls visit(descriptor) for every frame of a sequence, in order, reading it lazily (a query folder is
// listed first; a query of "-" reads one image path per line from standard input as the frames arrive).
void for_each_frame(const std::string& path, pipeline::InputKind kind, std::size_t every, const Describer& describe,
                    const std::function<void(FrameDescriptor)>& visit) {
  if (path == "-") {
    std::string line;
    while (std::getline(std::cin, line)) {
      if (line.empty()) continue;
      visit(describe(image::load_image(line)));
    }
    return;
  }
  const pipeline::SequenceInput input{path, kind, every};
  switch (pipeline::resolve_input_kind(input)) {
    case pipeline::InputKind::images:
      for (const auto& file : pipeline::list_images(path)) visit(describe(image::load_image(file)));
      return;
    case pipeline::InputKind::video:
      image::for_each_video_frame(path, every, [&](std::size_t, const RgbImage& frame) { visit(describe(frame)); });
      return;
    case pipeline::InputKind::descriptors: {
      const auto rows = io::read_npy_matrix<float>(path);
      if (rows.empty()) throw InputError(path, "no descriptors (empty array)");
      for (std::size_t i = 0; i < rows.rows; ++i) visit(std::vector<float>(rows.row(i).begin(), rows.row(i).end()));
      return;
    }
    default:
      break;
  }
  throw InputError(path, "expected an image folder, a video or descriptors.npy");
}

void run_online(const LocalizeOptions& o, const localize::LocalizeConfig& config, pipeline::InputKind kind, Run& run) {
  std::cout << "query,map,confidence,latency_ms\n";
  auto report = [&](const localize::OnlineEstimate& e, double seconds) {
    Answer a;
    if (e.in_map) a.map = e.map;
    a.score = e.confidence;
    a.candidates = {e.map};
    run.answers.push_back(a);
    run.latencies.push_back(seconds);
    std::cout << fmt::format("{},{},{:.4g},{:.3f}\n", e.query, e.in_map ? std::to_string(e.map) : std::string(),
                             e.confidence, 1e3 * seconds)
              << std::flush;
  };

  if (const auto file = similarity_file(o, kind)) {
    // The rows of a precomputed matrix arrive one by one.
    const auto s = io::read_npy_matrix<float>(*file);
    if (s.empty()) throw InputError(file->string(), "empty similarity matrix");
    localize::OnlineLocalizer localizer(s.cols, config);
    for (std::size_t i = 0; i < s.rows; ++i) {
      const auto t = Clock::now();
      const auto e = localizer.feed(s.row(i));
      report(e, seconds_since(t));
    }
    run.similarity = s;
    run.queries = s.rows;
    run.maps = s.cols;
    return;
  }

  // Image, video or descriptor inputs: the map is described once; each query frame then costs one
  // descriptor and one row of distances. The rows are contrast-enhanced, so S = 1 - kappa * D needs no kappa
  // (any kappa > 0 gives the same scores).
  const auto sc = similarity_config(o);
  const pipeline::InputKind map_kind = pipeline::resolve_input_kind({o.map_path, kind, o.every});
  const pipeline::Descriptor d =
      map_kind == pipeline::InputKind::descriptors ? pipeline::Descriptor::npy : sc.descriptor;
  if (d == pipeline::Descriptor::npy && map_kind != pipeline::InputKind::descriptors) {
    throw InputError("--descriptor", "npy needs descriptors .npy files as input");
  }
  const similarity::Distance metric = sc.distance.value_or(pipeline::default_distance(d));
  const Describer describe{d, sc};
  const auto t0 = Clock::now();
  std::vector<FrameDescriptor> map;
  for_each_frame(o.map_path, kind, o.every, describe, [&](FrameDescriptor f) { map.push_back(std::move(f)); });
  run.timings.emplace_back("map descriptors", seconds_since(t0));
  run.maps = map.size();
  localize::OnlineLocalizer localizer(map.size(), config);
  std::vector<float> row(map.size());
  std::vector<float> kept;
  auto t = Clock::now();  // a frame's latency runs from the end of the previous frame: reading it counts
  for_each_frame(o.query_path, kind, o.every, describe, [&](FrameDescriptor q) {
    try {
      for (std::size_t j = 0; j < map.size(); ++j) row[j] = static_cast<float>(-frame_distance(metric, q, map[j]));
    } catch (const std::invalid_argument& e) {
      throw InputError(o.query_path, e.what());
    }
    const auto e = localizer.feed(row);
    kept.insert(kept.end(), row.begin(), row.end());
    report(e, seconds_since(t));
    t = Clock::now();
  });
  run.queries = run.answers.size();
  if (run.queries == 0) throw InputError(o.query_path, "no query frame");
  run.similarity = SimilarityMatrix(run.queries, run.maps, std::move(kept));
}

// ---- outputs -----------------------------------------------------------------------------------------

std::vector<evaluation::LocalizationPrediction> predictions(const std::vector<Answer>& answers) {
  std::vector<evaluation::LocalizationPrediction> p;
  for (const auto& a : answers) p.push_back({a.map, a.score, a.candidates});
  return p;
}

nlohmann::json metrics_json(const evaluation::LocalizationMetrics& m) {
  nlohmann::json curve = nlohmann::json::array();
  for (const auto& p : m.curve)
    curve.push_back({{"threshold", p.threshold}, {"precision", p.precision}, {"recall", p.recall}});
  return {{"recall_at_1", m.recall_at_1},
          {"recall_at_5", m.recall_at_5},
          {"precision", m.precision},
          {"recall", m.recall},
          {"auc", m.auc},
          {"recall_at_100_precision", m.recall_at_100_precision},
          {"queries", m.queries},
          {"queries_with_match", m.queries_with_match},
          {"predicted", m.predicted},
          {"correct", m.correct},
          {"pr_curve", curve}};
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void run(const LocalizeOptions& o) {
  if (o.map_path.empty() && o.query_path.empty()) throw InputError("--map", "give --map and --query");
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  if (o.every == 0) throw InputError("--every", "must be at least 1");
  const auto config = localize_config(o);
  const bool have_matrix = [&] {
    for (const auto* p : {&o.map_path, &o.query_path}) {
      if (!p->empty() && *p != "-" && !fs::exists(*p)) throw InputError(*p, "does not exist");
    }
    return similarity_file(o, kind).has_value();
  }();
  if (!have_matrix && (o.map_path.empty() || o.query_path.empty())) {
    throw InputError(o.map_path.empty() ? "--map" : "--query", "is required unless a similarity.npy is given");
  }
  if (o.query_path == "-" && !o.online) throw InputError("--query", "'-' (paths on standard input) needs --online");

  // Ground truth is read before the work, so a bad file fails fast.
  std::optional<std::vector<std::pair<std::size_t, std::size_t>>> gt_pairs;
  const bool same_index = o.gt == "same-index";
  if (!o.gt.empty() && !same_index) {
    std::ifstream in(o.gt, std::ios::binary);
    if (!in) throw InputError(o.gt, "cannot open the ground-truth file");
    std::stringstream ss;
    ss << in.rdbuf();
    try {
      gt_pairs = evaluation::parse_pairs_csv(ss.str());
    } catch (const std::invalid_argument& e) {
      throw InputError(o.gt, e.what());
    }
  }

  Run r;
  const auto t0 = Clock::now();
  if (o.online) {
    run_online(o, config, kind, r);
  } else {
    run_offline(o, config, kind, r);
  }
  const double total = seconds_since(t0);

  // The ground truth must fit the sizes before anything is written.
  evaluation::LocalizationTruth truth;
  if (!o.gt.empty()) {
    try {
      truth = same_index ? evaluation::LocalizationTruth::same_index(r.queries, r.maps)
                         : evaluation::LocalizationTruth::from_pairs(*gt_pairs, r.queries, r.maps);
    } catch (const std::invalid_argument& e) {
      throw InputError(o.gt, e.what());
    }
  }

  io::OutputDirectory out(o.out_dir);
  std::string csv = "query,map,score\n";
  std::size_t not_in_map = 0;
  for (std::size_t q = 0; q < r.answers.size(); ++q) {
    const auto& a = r.answers[q];
    if (a.map) {
      csv += fmt::format("{},{},{:.6g}\n", q, *a.map, a.score);
    } else {
      csv += fmt::format("{},,\n", q);  // not in the map: empty map and score
      ++not_in_map;
    }
  }
  out.write("matches.csv", csv);

  // The similarity matrix with the alignments (red: forward, green: reverse) over it.
  std::vector<plot::Polyline> lines;
  for (const auto& a : r.alignments) {
    plot::Polyline line;
    for (const auto& [i, j] : a.pairs)
      line.points.emplace_back(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5);
    line.rgb = a.direction == align::Direction::forward ? std::array<std::uint8_t, 3>{230, 30, 30}
                                                        : std::array<std::uint8_t, 3>{30, 200, 60};
    line.thickness = 2;
    lines.push_back(std::move(line));
  }
  plot::MatrixImageConfig picture;
  picture.max_size = 1024;  // the report inlines it; block means keep the alignment lines visible
  out.write("similarity.png", plot::encode_png(plot::matrix_image(r.similarity, lines, picture)));

  std::optional<evaluation::LocalizationMetrics> metrics, single, seqslam;
  if (!o.gt.empty()) {
    metrics = evaluation::evaluate_localization(predictions(r.answers), truth, o.tolerance);
    // Baselines on the same matrix, for the PR chart.
    std::vector<Answer> sf;
    for (const auto& f : localize::single_frame_matches(r.similarity)) sf.push_back(answer_of(f));
    single = evaluation::evaluate_localization(predictions(sf), truth, o.tolerance);
    baseline::SeqSlamConfig sc;
    sc.sequence_length = 30;
    sc.min_velocity = 0.9F;
    sc.max_velocity = 1.6F;
    sc.velocity_steps = 8;
    sc.threads = resolve_threads(o.threads);
    std::vector<Answer> ss;
    for (const auto& m : baseline::seqslam_matches(r.similarity, sc)) {
      Answer a;
      // Only query frames with a whole sequence behind them are answered (the usual protocol).
      if (m.valid && m.query + 1 >= sc.sequence_length) a.map = m.match;
      a.score = m.score;
      a.candidates = {m.match};
      ss.push_back(a);
    }
    seqslam = evaluation::evaluate_localization(predictions(ss), truth, o.tolerance);

    nlohmann::json j = metrics_json(*metrics);
    j["tolerance"] = o.tolerance;
    j["mode"] = o.online ? "online" : "offline";
    j["baselines"] = {{"single_frame", metrics_json(*single)}, {"seqslam", metrics_json(*seqslam)}};
    out.write("metrics.json", j.dump(1) + "\n");

    std::vector<plot::Curve> curves(3);
    const std::pair<const char*, const evaluation::LocalizationMetrics*> named[3] = {
        {o.online ? "seqtopo online" : "seqtopo alignment", &*metrics},
        {"SeqSLAM (len 30)", &*seqslam},
        {"single frame", &*single}};
    const std::array<std::uint8_t, 3> colours[3] = {{220, 30, 30}, {40, 90, 220}, {120, 120, 120}};
    for (int k = 0; k < 3; ++k) {
      curves[static_cast<std::size_t>(k)].label = named[k].first;
      curves[static_cast<std::size_t>(k)].rgb = colours[k];
      for (const auto& p : named[k].second->curve)
        curves[static_cast<std::size_t>(k)].recall_precision.emplace_back(p.recall, p.precision);
    }
    out.write("pr_curve.png", plot::encode_png(plot::pr_curve_image(curves)));
  }

  std::vector<double> sorted = r.latencies;
  std::sort(sorted.begin(), sorted.end());
  auto percentile = [&](double p) {
    return sorted.empty()
               ? 0.0
               : sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
  };
  if (o.online) {
    std::string lat = "query,latency_ms\n";
    for (std::size_t q = 0; q < r.latencies.size(); ++q) lat += fmt::format("{},{:.4f}\n", q, 1e3 * r.latencies[q]);
    out.write("latency.csv", lat);
  }

  report::HtmlReport html(have_matrix ? "seqtopo localize: " + similarity_file(o, kind)->string()
                                      : "seqtopo localize: " + o.query_path + " in " + o.map_path);
  html.heading("Summary");
  std::vector<std::pair<std::string, std::string>> summary{
      {"mode", o.online ? "online (one frame at a time)" : "offline (whole query)"},
      {"query frames", std::to_string(r.queries)},
      {"map frames", std::to_string(r.maps)},
      {"frames not in the map", std::to_string(not_in_map)},
      {"seconds", fmt::format("{:.3f}", total)}};
  if (!o.online) summary.emplace_back("alignments", std::to_string(r.alignments.size()));
  if (o.online) {
    summary.emplace_back("latency per frame: median / 99% / max [ms]",
                         fmt::format("{:.3f} / {:.3f} / {:.3f}", 1e3 * percentile(0.5), 1e3 * percentile(0.99),
                                     sorted.empty() ? 0.0 : 1e3 * sorted.back()));
  }
  html.key_values(summary);
  if (metrics) {
    html.heading(fmt::format("Localization accuracy (tolerance +-{} frames)", o.tolerance));
    auto row = [](const std::string& name, const evaluation::LocalizationMetrics& m) {
      return std::vector<std::string>{name,
                                      fmt::format("{:.3f}", m.recall_at_1),
                                      fmt::format("{:.3f}", m.recall_at_5),
                                      fmt::format("{:.3f}", m.auc),
                                      fmt::format("{:.3f}", m.recall_at_100_precision),
                                      fmt::format("{:.3f}", m.precision),
                                      fmt::format("{:.3f}", m.recall)};
    };
    html.table({"method", "recall@1", "recall@5", "AUC", "R@100P", "precision", "recall"},
               {row(o.online ? "seqtopo online" : "seqtopo alignment", *metrics),
                row("SeqSLAM-style (len 30, v 0.9-1.6)", *seqslam), row("single frame", *single)});
    html.png("Precision-recall, sweeping the per-frame score threshold", read_file(out.staged("pr_curve.png")),
             "pr_curve.png");
  }
  html.heading("Similarity matrix");
  html.png(o.online ? "Query (rows) x map (columns) similarity"
                    : "Query (rows) x map (columns) similarity with the alignments: forward red, reverse green",
           read_file(out.staged("similarity.png")), "similarity.png");
  html.heading("Parameters");
  html.key_values({{"descriptor", o.descriptor},
                   {"gap", fmt::format("{}", config.gap)},
                   {"cap", config.cap ? fmt::format("{}", *config.cap) : "none"},
                   {"threshold", fmt::format("{}", config.threshold)},
                   {"offset [sd]", fmt::format("{}", config.offset)},
                   {"enhancement window [frames]", std::to_string(config.enhancement_window)},
                   {"score window [frames]", std::to_string(config.score_window)},
                   {"reverse pass", config.reverse ? "yes" : "no"}});
  if (!r.timings.empty()) {
    html.heading("Timings");
    std::vector<std::vector<std::string>> rows;
    for (const auto& [stage, seconds] : r.timings) rows.push_back({stage, fmt::format("{:.3f}", seconds)});
    html.table({"stage", "seconds"}, rows);
  }
  out.write("report.html", html.html());
  out.commit();

  std::string line = fmt::format("seqtopo localize: {} query frames in {} map frames, {} not in the map, {:.2f} s",
                                 r.queries, r.maps, not_in_map, total);
  if (metrics) {
    line += fmt::format("; recall@1 {:.3f}, AUC {:.3f}, R@100P {:.3f} (+-{} frames)", metrics->recall_at_1,
                        metrics->auc, metrics->recall_at_100_precision, o.tolerance);
  }
  if (o.online) {
    line += fmt::format("; latency per frame median {:.3f} ms, max {:.3f} ms", 1e3 * percentile(0.5),
                        sorted.empty() ? 0.0 : 1e3 * sorted.back());
  }
  std::cerr << line << " -> " << (out.dir() / "matches.csv").string() << "\n";
}

const RegisterCommand registered{
    {"localize",
     "Localize a query traverse in a mapped one by aligning image sequences (offline, or --online frame by frame)",
     [](CLI::App& app) {
       auto o = std::make_shared<LocalizeOptions>();
       app.add_option("--map", o->map_path,
                      "mapped traverse: image folder, video, descriptors.npy, or a query x map similarity.npy "
                      "(rows = query frames, columns = map frames; then --query is not needed)");
       app.add_option(
           "--query", o->query_path,
           "query traverse of the same kind ('-' with --online: image paths on standard input, one per line)");
       app.add_option("--out", o->out_dir, "output folder")->capture_default_str();
       app.add_option("--input-kind", o->input_kind, "auto|images|video|descriptors|similarity")->capture_default_str();
       app.add_option("--every", o->every, "video: keep every K-th frame")->capture_default_str();
       app.add_option("--descriptor", o->descriptor,
                      "patch|joint-histogram|panorama|npy (descriptors.npy inputs use their rows)")
           ->capture_default_str();
       app.add_option("--metric", o->metric, "chi2|l1|cosine|sad (default: by descriptor)");
       app.add_option("--kappa", o->kappa,
                      "K > 0 in S = 1 - K * D, or auto (rows are contrast-enhanced, so it rarely matters)");
       app.add_option("--gap", o->gap, "gap penalty per skipped frame [score units = standard deviations]")
           ->capture_default_str();
       app.add_option("--cap", o->cap, "upper bound on the cumulative score (default: none)");
       app.add_option("--threshold", o->threshold, "minimum alignment score (online: minimum confidence)")
           ->capture_default_str();
       app.add_option("--offset", o->offset, "subtracted from the contrast-enhanced similarity [standard deviations]")
           ->capture_default_str();
       app.add_option("--window", o->window, "contrast enhancement: +-W map frames (0 = whole row)")
           ->capture_default_str();
       app.add_option("--score-window", o->score_window, "per-frame score: +-W query frames of the alignment")
           ->capture_default_str();
       app.add_flag("--no-reverse", o->no_reverse, "do not search the map driven backwards");
       app.add_option("--gt", o->gt,
                      "ground truth: same-index (query k is map k) or a CSV file of query,map pairs; "
                      "also scores the single-frame and SeqSLAM baselines on the same matrix");
       app.add_option("--tolerance", o->tolerance, "a match within +-T map frames of the truth is correct")
           ->capture_default_str();
       app.add_flag("--online", o->online, "take query frames one at a time; print the best map frame after each");
       app.add_option("--threads", o->threads, "worker threads (0 = all cores)")->capture_default_str();
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli
