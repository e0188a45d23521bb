#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

void write_map_report(const pipeline::MapRun& run, io::OutputDirectory& out) {
  report::HtmlReport html("seqtopo map: " + run.input);
  const auto& result = run.result;
  const auto kept = std::count(result.pruning.kept.begin(), result.pruning.kept.end(), true);
  html.heading("Summary");
  html.key_values({{"images", std::to_string(result.map.labels.size())},
                   {"alignments (kept / found)", fmt::format("{} / {}", kept, result.alignments.size())},
                   {"alignments contradicted by odometry", std::to_string(result.rejected.size())},
                   {"loop-closure pairs retained", std::to_string(result.pruning.pairs.size())},
                   {"places", std::to_string(result.map.places.size())},
                   {"junctions", std::to_string(result.map.junctions.size())},
                   {"path segments", std::to_string(result.map.segments.size())}});
  if (run.metrics) {
    html.heading("Loop-closure accuracy");
    auto row = [](const std::string& name, const evaluation::LoopClosureMetrics& m) {
      return std::vector<std::string>{name,
                                      fmt::format("{:.3f}", m.precision),
                                      fmt::format("{:.3f}", m.recall),
                                      fmt::format("{:.3f}", m.f1),
                                      fmt::format("{:.3f}", m.auc),
                                      fmt::format("{:.3f}", m.recall_at_100_precision),
                                      fmt::format("{} / {} / {}", m.tp, m.fp, m.fn)};
    };
    std::vector<std::vector<std::string>> rows{row("seqtopo alignment", *run.metrics)};
    if (run.baseline_metrics) rows.push_back(row(run.baseline_name, *run.baseline_metrics));
    html.table({"method", "precision", "recall", "F1", "AUC", "R@100P", "TP / FP / FN"}, rows);
    if (!run.baseline_metrics && !run.baseline_skipped.empty())
      html.paragraph("Not compared: " + run.baseline_skipped + ".");
    html.png("Precision-recall, sweeping the score threshold", read_file(out.staged("pr_curve.png")), "pr_curve.png");
  }
  if (run.topology) {
    const auto& t = *run.topology;
    html.heading("Topological correctness");
    html.table(
        {"adjusted Rand index (places / images)", "false merges", "missed merges", "junctions true / found / matched"},
        {{fmt::format("{:.3f} / {:.3f}", t.adjusted_rand_index, t.adjusted_rand_index_frames),
          std::to_string(t.false_merges), std::to_string(t.missed_merges),
          fmt::format("{} / {} / {}", t.junctions_true, t.junctions_found, t.junctions_matched)}});
  }
  if (run.ate) {
    html.heading("Metric error (ATE, RMSE after rigid alignment)");
    html.table({"odometry [m]", "EKF [m]", "pose graph [m]"},
               {{fmt::format("{:.3f}", run.ate->odometry), fmt::format("{:.3f}", run.ate->ekf),
                 fmt::format("{:.3f}", run.ate->pose_graph)}});
  }
  html.heading("Similarity matrix and alignments");
  if (run.streaming) {
    html.png(
        fmt::format("Contrast-enhanced similarity, streamed: each pixel the maximum of a block of {0} x {0} scores "
                    "(bright = similar), with the alignments: kept pairs red, pruned blue",
                    run.overview.block),
        read_file(out.staged("similarity.png")), "similarity.png");
  } else {
    html.png(std::string(run.map_config.contrast_window > 0 ? "Contrast-enhanced similarity" : "Similarity matrix") +
                 " (bright = similar) with the alignments: kept pairs red, pruned blue",
             read_file(out.staged("similarity.png")), "similarity.png");
  }
  html.heading("Topological map");
  html.svg(run.result.map.places.size() <= kMaxDrawnPlaces
               ? "Places (red: junctions, blue: revisited places) and their connections"
               : "Junctions (red) and path ends joined by path segments (edge label: number of places)",
           read_file(out.staged("topology.svg")), "topology.svg");
  if (!run.odometry.empty()) {
    html.heading("Metric picture");
    html.png("Odometry beside the corrected map; dots coloured by place", read_file(out.staged("metric_map.png")),
             "metric_map.png");
  }
  html.heading("Parameters");
  const auto& c = run.map_config;
  std::vector<std::pair<std::string, std::string>> parameters{{"input", run.input}, {"preset", run.preset}};
  if (run.streaming) {
    const double n = static_cast<double>(result.map.labels.size());
    parameters.emplace_back("streaming",
                            "true: cosine similarity of the descriptors, contrast-enhanced on the fly "
                            "(scale/streaming_similarity.hpp), fast engine; no N x N matrix held");
    parameters.emplace_back("similarity cells computed during the alignment",
                            fmt::format("{} ({:.2f} x N^2, recomputations included)", run.streamed_cells,
                                        static_cast<double>(run.streamed_cells) / (n * n)));
    parameters.emplace_back("tile cache [MB]",
                            fmt::format("{:.1f}", static_cast<double>(run.streamed_cache_bytes) / 1e6));
  }
  std::string names;
  for (std::size_t k = 0; k < run.descriptor_names.size(); ++k) {
    names += (k ? ", " : "") + run.descriptor_names[k] +
             (k < run.similarities.size() ? fmt::format(" (kappa {:.4g})", run.similarities[k].kappa)
                                          : std::string(" (cosine)"));
  }
  parameters.emplace_back("descriptors", names);
  parameters.insert(parameters.end(),
                    {{"contrast enhancement", c.contrast_window > 0 ? fmt::format("window {} frames, offset {} sd",
                                                                                  c.contrast_window, c.contrast_offset)
                                                                    : "off"},
                     {"gap", fmt::format("{}", c.gap)},
                     {"cap", c.cap ? fmt::format("{}", *c.cap) : "none"},
                     {"threshold", fmt::format("{}", c.threshold)},
                     {"min separation [frames]", std::to_string(c.min_separation)},
                     {"reverse pass", c.reverse ? "yes" : "no"},
                     {"pruning: min retained fraction", fmt::format("{}", c.pruning.min_retained_fraction)}});
  html.key_values(parameters);
  html.heading("Timings");
  std::vector<std::vector<std::string>> rows;
  for (const auto& [stage, seconds] : run.timings) rows.push_back({stage, fmt::format("{:.3f}", seconds)});
  html.table({"stage", "seconds"}, rows);
  out.write("report.html", html.html());
}

}  // namespace seqtopo::outputs
