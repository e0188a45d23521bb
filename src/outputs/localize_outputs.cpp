#include "seqtopo/outputs/localize_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/plot/pr_curve.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

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

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

double latency_percentile(const pipeline::LocalizeRun& run, double p) {
  std::vector<double> sorted = run.latencies;
  std::sort(sorted.begin(), sorted.end());
  return sorted.empty()
             ? 0.0
             : sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
}

std::size_t write_localize_outputs(const pipeline::LocalizeRun& r, io::OutputDirectory& out) {
  const auto& config = r.settings.localize;
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

  const char* method = r.online ? "seqtopo online" : "seqtopo alignment";
  if (r.metrics) {
    nlohmann::json j = metrics_json(*r.metrics);
    j["tolerance"] = r.tolerance;
    j["mode"] = r.online ? "online" : "offline";
    j["baselines"] = {{"single_frame", metrics_json(*r.single_frame)}, {"seqslam", metrics_json(*r.seqslam)}};
    out.write("metrics.json", j.dump(1) + "\n");

    std::vector<plot::Curve> curves(3);
    const std::pair<const char*, const evaluation::LocalizationMetrics*> named[3] = {
        {method, &*r.metrics}, {"SeqSLAM (len 30)", &*r.seqslam}, {"single frame", &*r.single_frame}};
    const std::array<std::uint8_t, 3> colours[3] = {{220, 30, 30}, {40, 90, 220}, {120, 120, 120}};
    for (int k = 0; k < 3; ++k) {
      curves[static_cast<std::size_t>(k)].label = named[k].first;
      curves[static_cast<std::size_t>(k)].rgb = colours[k];
      for (const auto& p : named[k].second->curve)
        curves[static_cast<std::size_t>(k)].recall_precision.emplace_back(p.recall, p.precision);
    }
    out.write("pr_curve.png", plot::encode_png(plot::pr_curve_image(curves)));
  }

  if (r.online) {
    std::string lat = "query,latency_ms\n";
    for (std::size_t q = 0; q < r.latencies.size(); ++q) lat += fmt::format("{},{:.4f}\n", q, 1e3 * r.latencies[q]);
    out.write("latency.csv", lat);
  }

  report::HtmlReport html("seqtopo localize: " + r.inputs);
  html.heading("Summary");
  std::vector<std::pair<std::string, std::string>> summary{
      {"mode", r.online ? "online (one frame at a time)" : "offline (whole query)"},
      {"query frames", std::to_string(r.queries)},
      {"map frames", std::to_string(r.maps)},
      {"frames not in the map", std::to_string(not_in_map)},
      {"seconds", fmt::format("{:.3f}", r.seconds)}};
  if (!r.online) summary.emplace_back("alignments", std::to_string(r.alignments.size()));
  if (r.online) {
    summary.emplace_back("latency per frame: median / 99% / max [ms]",
                         fmt::format("{:.3f} / {:.3f} / {:.3f}", 1e3 * latency_percentile(r, 0.5),
                                     1e3 * latency_percentile(r, 0.99), 1e3 * latency_percentile(r, 1.0)));
  }
  html.key_values(summary);
  if (r.metrics) {
    html.heading(fmt::format("Localization accuracy (tolerance +-{} frames)", r.tolerance));
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
               {row(method, *r.metrics), row("SeqSLAM-style (len 30, v 0.9-1.6)", *r.seqslam),
                row("single frame", *r.single_frame)});
    html.png("Precision-recall, sweeping the per-frame score threshold", read_file(out.staged("pr_curve.png")),
             "pr_curve.png");
  }
  html.heading("Similarity matrix");
  html.png(r.online ? "Query (rows) x map (columns) similarity"
                    : "Query (rows) x map (columns) similarity with the alignments: forward red, reverse green",
           read_file(out.staged("similarity.png")), "similarity.png");
  html.heading("Parameters");
  html.key_values({{"descriptor", std::string(pipeline::descriptor_name(r.settings.similarity.descriptor))},
                   {"gap", fmt::format("{}", config.gap)},
                   {"cap", config.cap ? fmt::format("{}", *config.cap) : "none"},
                   {"threshold", fmt::format("{}", config.threshold)},
                   {"offset [sd]", fmt::format("{}", config.contrast_offset)},
                   {"enhancement window [frames]", std::to_string(config.contrast_window)},
                   {"score window [frames]", std::to_string(config.score_window)},
                   {"reverse pass", config.reverse ? "yes" : "no"}});
  if (!r.timings.empty()) {
    html.heading("Timings");
    std::vector<std::vector<std::string>> rows;
    for (const auto& [stage, seconds] : r.timings) rows.push_back({stage, fmt::format("{:.3f}", seconds)});
    html.table({"stage", "seconds"}, rows);
  }
  out.write("report.html", html.html());
  return not_in_map;
}

}  // namespace seqtopo::outputs
