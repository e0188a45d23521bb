// report.html of `seqtopo localize`: summary and accuracy, the interactive query x map matrix with the
// alignments and the matches over it (each match's query and map frames side by side), the PR curves of
// seqtopo and the baselines, the histogram of the per-frame confidence, parameters and timings.
#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "report_data.hpp"
#include "seqtopo/outputs/localize_outputs.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

// Every frame has its confidence, the probability its guess is right (online from the frames seen so far).
const char* confidence_label(const pipeline::LocalizeRun& r) {
  return r.online ? "confidence (probability the guess is right, from the frames so far)"
                  : "confidence (probability the guess is right)";
}

using detail::read_file;

detail::CurvePoints curve_points(const std::string& label, const std::string& colour,
                                 const evaluation::LocalizationMetrics& m) {
  detail::CurvePoints c{label, colour, {}};
  for (const auto& p : m.curve) c.points.push_back({p.recall, p.precision, p.threshold});
  return c;
}

}  // namespace

ReportResult write_localize_report(const pipeline::LocalizeRun& r, io::OutputDirectory& out,
                                   const ReportOptions& options) {
  const auto report_start = std::chrono::steady_clock::now();
  const auto& config = r.settings.localize;
  const char* method = r.online ? "seqtopo online" : "seqtopo alignment";
  std::size_t not_in_map = 0;
  for (const auto& a : r.answers) not_in_map += a.in_map ? 0 : 1;
  report::HtmlReport html("seqtopo localize: " + r.inputs);
  detail::provenance(html, options);
  nlohmann::json data = {{"kind", "localize"}, {"schema", 1}};
  html.heading("Summary");
  std::vector<std::pair<std::string, std::string>> summary{
      {"mode", r.online ? "online (one frame at a time)" : "offline (whole query)"},
      {"query frames", std::to_string(r.queries)},
      {"map frames", std::to_string(r.maps)},
      {fmt::format("frames not in the map (confidence < {})", config.min_confidence), std::to_string(not_in_map)},
      {"seconds", fmt::format("{:.3f}", r.seconds)}};
  if (!r.online) summary.emplace_back("alignments", std::to_string(r.alignments.size()));
  if (r.online) {
    summary.emplace_back("latency per frame (processing, from arrival to answer): median / 99% / max [ms]",
                         fmt::format("{:.3f} / {:.3f} / {:.3f}", 1e3 * latency_percentile(r, 0.5),
                                     1e3 * latency_percentile(r, 0.99), 1e3 * latency_percentile(r, 1.0)));
    double wait = 0;
    for (double w : r.waits) wait += w;
    summary.emplace_back("waiting for frames (not in the latency): total [s]", fmt::format("{:.3f}", wait));
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
               {row(method, *r.metrics), row("SeqSLAM", *r.seqslam), row("single frame", *r.single_frame)});
    html.paragraph("Recall@1 counts every query frame's best guess. SeqSLAM: " + r.seqslam_method +
                   ", on the same matrix; single frame: the most similar map frame.");
    if (r.decision) {
      html.paragraph(fmt::format(
          "In the map (confidence at least {}): {} frames, {} of them right (precision {:.3f}, recall {:.3f}).",
          config.min_confidence, r.decision->in_map, r.decision->correct, r.decision->precision, r.decision->recall));
    }
    html.raw(
        "<p class=\"note\">Precision-recall, sweeping the confidence threshold; seqtopo on top, the baselines dashed; "
        "hover for the values.</p><div id=\"pr-view\"></div><div class=\"readout\" id=\"pr-readout\"></div>\n");
    data["pr"] =
        detail::pr_json({curve_points(method, "#dc1e1e", *r.metrics), curve_points("SeqSLAM", "#285adc", *r.seqslam),
                         curve_points("single frame", "#787878", *r.single_frame)});
  }

  html.heading("Similarity matrix");
  html.raw(detail::matrix_view_markup(
      std::string("Query (rows) x map (columns) similarity (bright = similar)") +
      (r.online ? "" : ", alignments red (forward) and green (reverse)") +
      "; each query frame's match a yellow marker. Scroll or use the buttons to zoom, drag to pan; hover a "
      "marker to see the query frame beside its map frame."));
  html.raw("<div id=\"alignment-table\"></div>\n");
  data["matrix"] =
      detail::matrix_json(r.similarity, r.similarity.rows, r.similarity.cols, "query frame", "map frame", "similarity");
  nlohmann::json alignments = nlohmann::json::array();
  for (std::size_t k = 0; k < r.alignments.size(); ++k)
    alignments.push_back(detail::alignment_json(r.alignments[k], k, true));
  data["alignments"] = std::move(alignments);
  nlohmann::json rows = nlohmann::json::array(), values = nlohmann::json::array();
  std::vector<std::size_t> wanted_q, wanted_m;
  for (std::size_t q = 0; q < r.answers.size(); ++q) {
    const auto& a = r.answers[q];
    if (!a.map) continue;
    nlohmann::json row = {{"i", q}, {"j", *a.map}, {"score", a.score}, {"confidence", a.confidence}};
    row["in_map"] = a.in_map ? "yes" : "no";
    if (std::isfinite(a.e_value)) row["e_value"] = a.e_value;
    if (q < r.latencies.size()) row["latency_ms"] = 1e3 * r.latencies[q];
    values.push_back(a.confidence);
    rows.push_back(std::move(row));
    wanted_q.push_back(q);
    wanted_m.push_back(*a.map);
  }
  nlohmann::json fields = {{{"key", "i"}, {"label", "query frame"}},
                           {{"key", "j"}, {"label", "map frame"}},
                           {{"key", "score"}, {"label", "local score"}},
                           {{"key", "confidence"}, {"label", "confidence"}}};
  fields.push_back({{"key", "e_value"}, {"label", r.online ? "E-value (frames so far)" : "E-value of its alignment"}});
  fields.push_back({{"key", "in_map"}, {"label", "in the map"}});
  if (r.online) fields.push_back({{"key", "latency_ms"}, {"label", "latency [ms]"}});
  data["pairs"] = {{"singular", "Match"},
                   {"css", "match"},
                   {"row_name", "query frame"},
                   {"col_name", "map frame"},
                   {"confidence", {{"key", "confidence"}, {"label", confidence_label(r)}}},
                   {"fields", std::move(fields)},
                   {"rows", std::move(rows)}};
  data["sequences"] = {
      {"rows", detail::sequence_json(r.query_input, r.queries, wanted_q, "query frame", options.thumbnails)},
      {"cols", detail::sequence_json(r.map_input, r.maps, wanted_m, "map frame", options.column_thumbnails)}};
  if (data["sequences"]["rows"]["note"] != "") {
    html.paragraph("Images: " + data["sequences"]["rows"]["note"].get<std::string>() + ".");
  }

  html.heading("Confidence of the matches");
  html.raw("<p class=\"note\">Histogram of the query frames' " + report::escape_html(confidence_label(r)) +
           "; hover a bar for its count.</p><div id=\"confidence-view\"></div>"
           "<div class=\"readout\" id=\"confidence-readout\"></div>\n");
  data["histogram"] = {{"label", confidence_label(r)}, {"unit", "query frames"}, {"values", std::move(values)}};
  if (r.calibration) detail::reliability_section(html, *r.calibration, "query frames");

  html.heading("Parameters");
  std::vector<std::pair<std::string, std::string>> parameters{
      {"descriptor", pipeline::descriptor_names(r.settings.descriptors)},
      {"gap", fmt::format("{}", config.search.gap)},
      {"cap", config.search.cap ? fmt::format("{}", *config.search.cap) : "none"},
      {"threshold", fmt::format("{}", config.significance.threshold)},
      {"minimum confidence (in the map)", fmt::format("{}", config.min_confidence)},
      {"posterior band [frames] / tolerance [map frames]",
       fmt::format("{} / {}", config.posterior_band, config.tolerance)},
      {"offset [sd]", fmt::format("{}", config.score.contrast_offset)},
      {"enhancement window [frames]", std::to_string(config.score.contrast_window)},
      {"score window [frames]", std::to_string(config.score_window)},
      {"reverse pass", config.search.reverse ? "yes" : "no"}};
  if (r.online)
    parameters.emplace_back("online: lag [frames] (each frame answered this many frames later)",
                            std::to_string(config.lag));
  html.key_values(parameters);
  data["parameters"] = parameters;

  html.heading("Static figures (the PNG files, for papers)");
  html.begin_details(r.metrics ? "similarity.png, pr_curve.png" : "similarity.png");
  if (r.metrics) {
    html.png(r.online ? "Precision-recall, sweeping the per-frame score threshold"
                      : "Precision-recall, sweeping the confidence threshold",
             read_file(out.staged("pr_curve.png")), "pr_curve.png");
  }
  html.png(r.online ? "Query (rows) x map (columns) similarity"
                    : "Query (rows) x map (columns) similarity with the alignments: forward red, reverse green",
           read_file(out.staged("similarity.png")), "similarity.png");
  html.end_details();

  html.heading("Timings");
  html.raw(
      "<p class=\"note\">Every stage of the run, one after the other: they add up to the wall time.</p>"
      "<div id=\"timings-view\"></div><div class=\"readout\" id=\"timings-readout\"></div>\n");
  auto timings = r.timings;
  data["timings"] = detail::timings_json(timings, options, report_start);
  std::vector<std::vector<std::string>> table;
  for (const auto& [stage, seconds] : timings) table.push_back({stage, fmt::format("{:.3f}", seconds)});
  table.push_back({"wall time", fmt::format("{:.3f}", data["timings"]["wall"].get<double>())});
  html.table({"stage", "seconds"}, table);
  const ReportResult status = detail::finish_interactive(html, data);
  out.write("report.html", html.html());
  return status;
}

}  // namespace seqtopo::outputs
