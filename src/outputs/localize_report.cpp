#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "seqtopo/outputs/localize_outputs.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

void write_localize_report(const pipeline::LocalizeRun& r, io::OutputDirectory& out) {
  const auto& config = r.settings.localize;
  const char* method = r.online ? "seqtopo online" : "seqtopo alignment";
  std::size_t not_in_map = 0;
  for (const auto& a : r.answers) not_in_map += a.map ? 0 : 1;
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
}

}  // namespace seqtopo::outputs
