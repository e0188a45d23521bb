#include "seqtopo/outputs/localize_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "figures.hpp"
#include "report_data.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/plot/pr_curve.hpp"

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

}  // namespace

double latency_percentile(const pipeline::LocalizeRun& run, double p) {
  std::vector<double> sorted = run.latencies;
  std::sort(sorted.begin(), sorted.end());
  return sorted.empty()
             ? 0.0
             : sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
}

std::size_t write_localize_outputs(const pipeline::LocalizeRun& r, io::OutputDirectory& out) {
  // Every frame has its best guess and the decision on its confidence (online from the frames so far).
  std::string csv = "query,map,score,confidence,e_value,in_map\n";
  std::size_t not_in_map = 0;
  for (std::size_t q = 0; q < r.answers.size(); ++q) {
    const auto& a = r.answers[q];
    not_in_map += a.in_map ? 0 : 1;
    if (a.map) {
      csv += fmt::format("{},{},{:.6g},{:.6g},{},{}\n", q, *a.map, a.score, a.confidence,
                         std::isfinite(a.e_value) ? fmt::format("{:.4g}", a.e_value) : std::string(), a.in_map ? 1 : 0);
    } else {
      csv += fmt::format("{},,,{:.6g},,0\n", q, a.confidence);
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
  out.write("similarity.png",
            plot::encode_png(plot::matrix_figure(r.similarity, lines, localize_similarity_figure(r))));

  const char* method = r.online ? "seqtopo online" : "seqtopo alignment";
  if (r.metrics) {
    nlohmann::json j = metrics_json(*r.metrics);
    j["seqtopo_version"] = std::string(version());
    j["tolerance"] = r.tolerance;
    j["mode"] = r.online ? "online" : "offline";
    if (r.online) j["lag"] = r.settings.localize.lag;
    j["ranked_by"] = "confidence";
    j["baselines"] = {{"single_frame", metrics_json(*r.single_frame)}, {"seqslam", metrics_json(*r.seqslam)}};
    j["baselines"]["seqslam"]["method"] = r.seqslam_method;
    if (r.decision) {
      j["in_map"] = {{"min_confidence", r.settings.localize.min_confidence},
                     {"frames", r.decision->in_map},
                     {"correct", r.decision->correct},
                     {"precision", r.decision->precision},
                     {"recall", r.decision->recall}};
    }
    if (r.calibration) j["calibration"] = detail::calibration_json(*r.calibration, "frames");
    if (r.statistics.valid()) {
      j["significance"] = {{"lambda", r.statistics.lambda}, {"k", r.statistics.k}, {"area", r.statistics.area}};
    }
    nlohmann::json timings = nlohmann::json::array();
    for (const auto& [stage, seconds] : r.timings) timings.push_back({{"stage", stage}, {"seconds", seconds}});
    j["timings"] = timings;
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
    std::string lat = "query,latency_ms,wait_ms\n";
    for (std::size_t q = 0; q < r.latencies.size(); ++q) {
      lat += fmt::format("{},{:.4f},{:.4f}\n", q, 1e3 * r.latencies[q], q < r.waits.size() ? 1e3 * r.waits[q] : 0.0);
    }
    out.write("latency.csv", lat);
  }

  return not_in_map;
}

}  // namespace seqtopo::outputs
