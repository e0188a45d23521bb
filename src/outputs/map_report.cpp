// report.html of `seqtopo map`: the summary and accuracy tables, the interactive views (the similarity matrix
// with the alignments and loop closures over it, each pair's two images, the topology with its places and
// junctions, the PR curve and the histogram of the pairs' confidence, the stage timings), and the static
// figures written beside it.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include "figures.hpp"
#include "report_data.hpp"
#include "seqtopo/formats/decision_notes.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

// The per-pair value the histogram shows and the pair viewer names "confidence" (mapping/pruning.hpp).
constexpr const char* kConfidenceKey = "confidence";
constexpr const char* kConfidenceLabel = "confidence (P the pair is a revisit)";

using detail::read_file;

// {"fields": [{"key", "label"}], "rows": [{"i", "j", ...}]}: the fields the pair viewer shows, in order. A new
// per-pair field (confidence, E-value) is one more key in each row and one more entry in `fields`.
nlohmann::json pairs_json(const pipeline::MapRun& run) {
  const auto& result = run.result;
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& p : result.pruning.pairs) {
    const auto& a = result.alignments[p.alignment];
    rows.push_back({{"i", p.i},
                    {"j", p.j},
                    {"confidence", p.confidence},
                    {"score", p.score},
                    {"e_value", p.alignment < result.e_values.size() && std::isfinite(result.e_values[p.alignment])
                                    ? nlohmann::json(result.e_values[p.alignment])
                                    : nlohmann::json(nullptr)},
                    {"alignment", p.alignment},
                    {"direction", std::string(align::to_string(a.direction))}});
  }
  return {{"singular", "Loop closure"},
          {"css", "loop-closure"},
          {"row_name", "image"},
          {"col_name", "image"},
          {"confidence", {{"key", kConfidenceKey}, {"label", kConfidenceLabel}}},
          {"fields",
           {{{"key", "i"}, {"label", "image i (later)"}},
            {{"key", "j"}, {"label", "image j (earlier)"}},
            {{"key", "confidence"}, {"label", "confidence"}},
            {{"key", "score"}, {"label", "alignment score"}},
            {{"key", "e_value"}, {"label", "alignment E-value"}},
            {{"key", "alignment"}, {"label", "alignment #"}},
            {{"key", "direction"}, {"label", "direction"}}}},
          {"rows", std::move(rows)}};
}

// The drawn topology: every place when there are few (kMaxDrawnPlaces), else junctions, path ends and runs of
// places along each path segment (at most 12 per segment), so that a loop is drawn as a loop.
nlohmann::json topology_json(const mapping::TopologicalMap& map) {
  std::vector<bool> junction(map.places.size(), false);
  for (auto j : map.junctions) junction[static_cast<std::size_t>(j)] = true;
  nlohmann::json nodes = nlohmann::json::array(), links = nlohmann::json::array();
  const auto place_label = [&](mapping::PlaceLabel p) {
    const auto& images = map.places[static_cast<std::size_t>(p)].images;
    std::string text =
        fmt::format("{} {}: {} image{}", junction[static_cast<std::size_t>(p)] ? "junction, place" : "place", p,
                    images.size(), images.size() == 1 ? "" : "s");
    for (std::size_t k = 0; k < images.size() && k < 8; ++k) text += (k ? ", " : " (") + std::to_string(images[k]);
    return text + (images.size() > 8 ? ", ...)" : ")");
  };
  const bool collapsed = map.places.size() > kMaxDrawnPlaces;
  if (!collapsed) {
    for (const auto& place : map.places) {
      nodes.push_back({{"id", place.id},
                       {"kind", junction[static_cast<std::size_t>(place.id)] ? "junction" : "place"},
                       {"places", {place.id}},
                       {"images", place.images.size()},
                       {"label", place_label(place.id)}});
    }
    for (auto [p, q] : map.edges) links.push_back({p, q, 1});
  } else {
    std::map<mapping::PlaceLabel, std::size_t> end_node;  // junctions and path ends: one node each
    auto end_of = [&](mapping::PlaceLabel p) {
      if (const auto it = end_node.find(p); it != end_node.end()) return it->second;
      const std::size_t id = nodes.size();
      nodes.push_back({{"id", id},
                       {"kind", junction[static_cast<std::size_t>(p)] ? "junction" : "place"},
                       {"places", {p}},
                       {"images", map.places[static_cast<std::size_t>(p)].images.size()},
                       {"label", place_label(p)}});
      end_node[p] = id;
      return id;
    };
    for (const auto& s : map.segments) {
      if (s.places.empty()) continue;
      const std::size_t first = end_of(s.places.front());
      std::size_t previous = first;
      const std::size_t inner = s.places.size() > 2 ? s.places.size() - 2 : 0;
      const std::size_t runs = std::min<std::size_t>(12, inner);
      for (std::size_t r = 0; r < runs; ++r) {
        const std::size_t begin = 1 + r * inner / runs, end = 1 + (r + 1) * inner / runs;
        std::vector<mapping::PlaceLabel> places(s.places.begin() + static_cast<std::ptrdiff_t>(begin),
                                                s.places.begin() + static_cast<std::ptrdiff_t>(end));
        std::size_t images = 0;
        for (auto p : places) images += map.places[static_cast<std::size_t>(p)].images.size();
        const std::size_t id = nodes.size();
        nodes.push_back({{"id", id},
                         {"kind", "run"},
                         {"places", places},
                         {"images", images},
                         {"label", fmt::format("places {} to {} along a path segment ({} places, {} images)",
                                               places.front(), places.back(), places.size(), images)}});
        links.push_back({previous, id, places.size()});
        previous = id;
      }
      if (s.places.size() > 1) links.push_back({previous, end_of(s.places.back()), 1});
    }
  }
  nlohmann::json places = nlohmann::json::array();
  for (const auto& p : map.places) places.push_back(p.images);
  nlohmann::json junctions = nlohmann::json::array();
  // The evidence of each junction (topological_map.hpp), as text the page lists key by key.
  const auto joined = [](const auto& values) {
    std::string text;
    for (const auto& v : values) text += (text.empty() ? "" : ", ") + fmt::format("{}", v);
    return text.empty() ? std::string("none") : text;
  };
  for (const auto& j : map.junction_evidence) {
    std::string passes;
    for (const auto& p : j.passes) {
      const auto place = [](mapping::PlaceLabel q) { return q < 0 ? std::string("start/end") : fmt::format("{}", q); };
      passes += fmt::format("{}images {}-{}: {} -> {} (session {})", passes.empty() ? "" : "; ", p.first_image,
                            p.last_image, place(p.from), place(p.to), p.session);
    }
    std::string reasons = j.by_degree ? "three or more neighbouring places" : "";
    if (j.by_alignment) reasons += std::string(reasons.empty() ? "" : "; ") + "an alignment's traversals part here";
    junctions.push_back({{"place", j.place},
                         {"evidence",
                          {{"why", reasons},
                           {"branches", joined(j.branches)},
                           {"join / leave images", joined(j.images)},
                           {"alignments", joined(j.alignments)},
                           {"sessions", joined(j.sessions)},
                           {"passes", passes},
                           {"confidence", fmt::format("{:.3f}", j.confidence)}}}});
  }
  return {{"collapsed", collapsed},
          {"nodes", std::move(nodes)},
          {"links", std::move(links)},
          {"places", std::move(places)},
          {"junctions", std::move(junctions)}};
}

// The thumbnails of several sessions, one after the other in the run's image order.
nlohmann::json sessions_json(const pipeline::MapRun& run, const std::vector<std::size_t>& wanted,
                             const std::vector<std::string>* jpegs) {
  nlohmann::json names = nlohmann::json::array(), thumbs = nlohmann::json::array();
  std::string note;
  int side = 0;
  for (std::size_t k = 0; k < run.sessions.size(); ++k) {
    const auto& session = run.sessions[k];
    std::vector<std::size_t> local;
    for (auto w : wanted) {
      if (w >= session.begin && w < session.end) local.push_back(w - session.begin);
    }
    std::vector<std::string> own;  // the session's thumbnails made while the run read its images, if any
    if (jpegs != nullptr && jpegs->size() >= session.end) {
      own.assign(jpegs->begin() + static_cast<std::ptrdiff_t>(session.begin),
                 jpegs->begin() + static_cast<std::ptrdiff_t>(session.end));
    }
    const auto part = detail::sequence_json(run.session_inputs[k], session.end - session.begin, local, "image",
                                            own.empty() ? nullptr : &own);
    for (const auto& name : part["names"])
      names.push_back(fmt::format("session {}: {}", k + 1, name.get<std::string>()));
    for (const auto& t : part["thumbnails"]) thumbs.push_back(t);
    if (!part["note"].get<std::string>().empty())
      note += (note.empty() ? "" : "; ") + fmt::format("session {}: {}", k + 1, part["note"].get<std::string>());
    side = part["thumbnail_side"].get<int>();
  }
  return {{"count", names.size()},           {"noun", "image"}, {"names", std::move(names)},
          {"thumbnails", std::move(thumbs)}, {"note", note},    {"thumbnail_side", side}};
}

// {"false_positives": [[i, j, score]], "missed": [[i, partner]]}: the matrix view marks them.
nlohmann::json errors_json(const evaluation::LoopClosureErrors& e) {
  nlohmann::json fp = nlohmann::json::array(), missed = nlohmann::json::array();
  for (const auto& p : e.false_positives) fp.push_back({p.i, p.j, p.score});
  for (const auto& m : e.missed) {
    if (m.partner != m.i) missed.push_back({m.i, m.partner});
  }
  return {{"false_positives", std::move(fp)}, {"missed", std::move(missed)}};
}

// The errors listed with the two images of each (when the sequence has images): what the user looks at first.
void errors_section(report::HtmlReport& html, const evaluation::LoopClosureErrors& e, const nlohmann::json& sequence) {
  constexpr std::size_t kListed = 50;
  const auto image = [&](std::size_t k) {
    const auto& thumbs = sequence["thumbnails"];
    if (k < thumbs.size() && thumbs[k].is_string()) {
      return "<img class=\"error-thumb\" alt=\"image " + std::to_string(k) + "\" src=\"" +
             thumbs[k].get<std::string>() + "\">";
    }
    return std::string();
  };
  const auto name = [&](std::size_t k) {
    const auto& names = sequence["names"];
    std::string text = std::to_string(k);
    if (k < names.size() && names[k].is_string() && !names[k].get<std::string>().empty())
      text += " (" + report::escape_html(names[k].get<std::string>()) + ")";
    return text;
  };
  html.heading("Where the map is wrong");
  std::string body =
      "<p class=\"note\">Counted as in the accuracy table: a false positive is an image's best retained pair "
      "whose two images the ground truth calls different places; a missed revisit is an image the ground truth "
      "says was seen before (at least the minimum separation earlier) with no true detection, shown beside its "
      "nearest true partner. The first " +
      std::to_string(kListed) + " of each are listed.</p>\n";
  const auto table = [&](const std::string& caption, const std::vector<std::array<std::string, 3>>& rows,
                         std::size_t total) {
    body += "<h3>" + caption + fmt::format(" ({})", total) + "</h3>\n";
    if (rows.empty()) {
      body += "<p>None.</p>\n";
      return;
    }
    body += "<table class=\"errors\"><tr><th>image i</th><th>image j</th><th>what</th></tr>\n";
    for (const auto& [a, b, what] : rows)
      body += "<tr><td>" + a + "</td><td>" + b + "</td><td>" + what + "</td></tr>\n";
    body += "</table>\n";
  };
  std::vector<std::array<std::string, 3>> rows;
  for (std::size_t k = 0; k < e.false_positives.size() && k < kListed; ++k) {
    const auto& p = e.false_positives[k];
    rows.push_back({image(p.i) + "<br>" + name(p.i), image(p.j) + "<br>" + name(p.j),
                    fmt::format("detected with confidence {:.3f}; not the same place", p.score)});
  }
  table("False positives", rows, e.false_positives.size());
  rows.clear();
  for (std::size_t k = 0; k < e.missed.size() && k < kListed; ++k) {
    const auto& m = e.missed[k];
    rows.push_back({image(m.i) + "<br>" + name(m.i),
                    m.partner != m.i ? image(m.partner) + "<br>" + name(m.partner) : std::string("(not looked up)"),
                    "the same place; no true detection for image i"});
  }
  table("Missed revisits", rows, e.missed.size());
  html.raw(body);
}

detail::CurvePoints curve_points(const std::string& label, const std::string& colour,
                                 const evaluation::LoopClosureMetrics& m) {
  detail::CurvePoints c{label, colour, {}};
  for (const auto& p : m.curve) c.points.push_back({p.recall, p.precision, p.threshold});
  return c;
}

}  // namespace

ReportResult write_map_report(const pipeline::MapRun& run, io::OutputDirectory& out, const ReportOptions& options) {
  const auto report_start = std::chrono::steady_clock::now();
  report::HtmlReport html("seqtopo map: " + run.input);
  detail::provenance(html, options);
  const auto& result = run.result;
  const std::size_t n = result.map.labels.size();
  const auto kept = std::count(result.pruning.kept.begin(), result.pruning.kept.end(), true);
  html.heading("Summary");
  html.key_values({{"images", std::to_string(n)},
                   {"alignments (kept / found)", fmt::format("{} / {}", kept, result.alignments.size())},
                   {"alignments contradicted by odometry", std::to_string(result.rejected.size())},
                   {"loop-closure pairs retained", std::to_string(result.pruning.pairs.size())},
                   {"places", std::to_string(result.map.places.size())},
                   {"junctions", std::to_string(result.map.junctions.size())},
                   {"path segments", std::to_string(result.map.segments.size())}});
  nlohmann::json data = {{"kind", "map"}, {"schema", 1}};
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
    html.raw(
        "<p class=\"note\">Precision-recall, sweeping the pairs' confidence threshold; hover for the values "
        "(the static figure is pr_curve.png).</p><div id=\"pr-view\"></div>"
        "<div class=\"readout\" id=\"pr-readout\"></div>\n");
    if (run.errors) {
      html.paragraph(
          fmt::format("{} false positive{} and {} missed revisit{}: marked on the similarity matrix below "
                      "(magenta and yellow squares) and listed with their images under \"Where the map "
                      "is wrong\".",
                      run.errors->false_positives.size(), run.errors->false_positives.size() == 1 ? "" : "s",
                      run.errors->missed.size(), run.errors->missed.size() == 1 ? "" : "s"));
    }
    std::vector<detail::CurvePoints> curves{curve_points("seqtopo alignment", "#dc1e1e", *run.metrics)};
    if (run.baseline_metrics) curves.push_back(curve_points(run.baseline_name, "#285adc", *run.baseline_metrics));
    data["pr"] = detail::pr_json(curves);
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

  // What the significance statistics decided, and what the filter removed.
  const auto& d = result.decisions;
  const std::vector<std::string> notes = formats::decision_notes(d, run.descriptor_names);
  if (d.statistics.valid() || !notes.empty() || !result.insignificant.empty()) {
    html.heading("Significance: what was kept and what was removed");
    std::vector<std::pair<std::string, std::string>> facts{
        {"frames per place",
         fmt::format("{:.2f} ({})", d.frames_per_place, d.frames_per_place_estimated ? "estimated" : "given")},
        {"contrast offset aligned with [sd]", fmt::format("{:.2f}", d.contrast_offset)},
        {"cap", d.cap ? fmt::format("{:.1f}", *d.cap) : "none"},
        {"score a revisit needs", fmt::format("{:.1f}", d.score_threshold)}};
    if (d.statistics.valid()) {
      facts.emplace_back("lambda, K (extreme-value fit)",
                         fmt::format("{:.3f}, {:.3g} ({} chance alignments)", d.statistics.lambda, d.statistics.k,
                                     d.statistics.fitted));
    }
    facts.emplace_back("alignments removed as chance or shorter than a revisit",
                       std::to_string(result.insignificant.size()));
    if (!d.low_information_frames.empty()) {
      // Stretches, as a person reads them: first-last images of each run of masked frames.
      std::string stretches;
      for (const auto& [first, last] : formats::frame_stretches(d.low_information_frames)) {
        stretches += (stretches.empty() ? "" : ", ") +
                     (first == last ? std::to_string(first) : fmt::format("{}-{}", first, last));
      }
      facts.emplace_back("images of little information (masked: no evidence of a revisit)",
                         fmt::format("{}: {}", d.low_information_frames.size(), stretches));
    }
    if (!run.session_breaks.empty()) {
      std::string breaks;
      for (const auto& b : run.session_breaks) {
        breaks +=
            fmt::format("{}before image {} ({:.3g} s without a frame)", breaks.empty() ? "" : ", ", b.frame, b.gap);
      }
      facts.emplace_back("session breaks found (no topological edge across them)", breaks);
    }
    html.key_values(facts);
    for (const auto& note : notes) html.paragraph(note);
    if (!result.insignificant.empty()) {
      constexpr std::size_t kListed = 20;
      std::vector<std::vector<std::string>> rows;
      for (std::size_t k = 0; k < result.insignificant.size() && k < kListed; ++k) {
        const auto& a = result.insignificant[k];
        const double e = k < result.insignificant_e_values.size() ? result.insignificant_e_values[k] : std::nan("");
        rows.push_back({std::to_string(k + 1), std::string(align::to_string(a.direction)),
                        fmt::format("{:.2f}", a.score), std::isfinite(e) ? fmt::format("{:.3g}", e) : "",
                        fmt::format("{}-{}", a.a_begin, a.a_end - 1), fmt::format("{}-{}", a.b_begin, a.b_end - 1),
                        std::to_string(a.pairs.size())});
      }
      html.paragraph(
          fmt::format("The best {} of the removed alignments (all are in alignments.json, "
                      "\"insignificant\"):",
                      rows.size()));
      html.table({"rank", "direction", "score", "E-value", "images i", "images j", "pairs"}, rows);
    }
  }

  // The matrix view: the aligned scores (or their block-max overview), alignments and loop closures over it.
  html.heading("Similarity matrix and alignments");
  const DrawnMatrix drawn(run);  // what similarity.png draws
  const std::string what = run.streamed() ? "Contrast-enhanced similarity (streamed: block maxima)"
                                          : (run.map_config.score.contrast_window > 0 ? "Contrast-enhanced similarity"
                                                                                      : "Similarity S = 1 - kappa D") +
                                                (drawn.block() > 1 ? std::string(" (block maxima)") : std::string());
  html.raw(detail::matrix_view_markup(
      what +
      " of every pair of images (bright = similar): kept alignments red, pruned ones dashed blue, each "
      "retained loop-closure pair a yellow marker. Scroll or use the buttons to zoom, drag to pan; hover a "
      "marker to see its two images, click a cell for any pair." +
      (run.errors
           ? std::string(" Against the ground truth: each false positive a magenta square, each missed revisit a "
                         "yellow square at its nearest true pair (listed under \"Where the map is wrong\").")
           : std::string())));
  html.raw("<div id=\"alignment-table\"></div>\n");
  data["matrix"] = detail::matrix_json(drawn.cells(), n, n, "image i", "image j",
                                       run.streamed() || run.map_config.score.contrast_window > 0 ? "score [sd]" : "S");
  nlohmann::json alignments = nlohmann::json::array();
  for (std::size_t k = 0; k < result.alignments.size(); ++k) {
    alignments.push_back(
        detail::alignment_json(result.alignments[k], k, k < result.pruning.kept.size() && result.pruning.kept[k]));
  }
  data["alignments"] = std::move(alignments);
  data["pairs"] = pairs_json(run);
  std::vector<std::size_t> wanted;
  if (run.errors) {  // the errors' images first: the report lists them
    for (const auto& p : run.errors->false_positives) wanted.push_back(p.i), wanted.push_back(p.j);
    for (const auto& m : run.errors->missed) wanted.push_back(m.i), wanted.push_back(m.partner);
    data["errors"] = errors_json(*run.errors);
  }
  for (const auto& p : result.pruning.pairs) wanted.push_back(p.i), wanted.push_back(p.j);
  data["sequences"] = {{"rows", run.session_inputs.size() > 1 && run.session_inputs.size() == run.sessions.size()
                                    ? sessions_json(run, wanted, options.thumbnails)
                                    : detail::sequence_json(run.sequence, n, wanted, "image", options.thumbnails)},
                       {"cols", "rows"}};
  if (data["sequences"]["rows"]["note"] != "") {
    html.paragraph("Images: " + data["sequences"]["rows"]["note"].get<std::string>() + ".");
  }
  if (run.errors) errors_section(html, *run.errors, data["sequences"]["rows"]);

  html.heading("Confidence of the loop closures");
  html.raw("<p class=\"note\">Histogram of the retained pairs' " + report::escape_html(kConfidenceLabel) +
           "; hover a bar for its count.</p><div id=\"confidence-view\"></div>"
           "<div class=\"readout\" id=\"confidence-readout\"></div>\n");
  nlohmann::json values = nlohmann::json::array();
  for (const auto& row : data["pairs"]["rows"]) values.push_back(row[kConfidenceKey]);
  data["histogram"] = {{"label", kConfidenceLabel}, {"unit", "pairs"}, {"values", std::move(values)}};

  if (run.calibration) {
    html.heading("Calibration of the confidence");
    detail::reliability_section(html, *run.calibration, "loop-closure pairs");
  }

  html.heading("Topological map");
  html.raw(std::string("<p class=\"note\">") +
           (result.map.places.size() <= kMaxDrawnPlaces
                ? "Places (blue: revisited, grey: seen once, red: junctions) and their connections. "
                : "Junctions (red), path ends and runs of places along each path segment (light blue). ") +
           "Click a node to see its images; scroll to zoom, drag to pan.</p>"
           "<div class=\"view\"><div id=\"topology-view\"></div>"
           "<div class=\"panel\" id=\"place-viewer\"><span class=\"note\">Click a place or a junction.</span></div>"
           "</div>\n");
  data["topology"] = topology_json(result.map);

  if (!run.odometry.empty()) {
    html.heading("Metric picture");
    html.png("Odometry beside the corrected map; dots coloured by place", read_file(out.staged("metric_map.png")),
             "metric_map.png");
  }
  html.heading("Parameters");
  const auto& c = run.map_config;
  std::vector<std::pair<std::string, std::string>> parameters{{"input", run.input}, {"preset", run.preset}};
  if (run.streamed()) {
    const double nn = static_cast<double>(n);
    parameters.emplace_back("streaming",
                            "true: cosine similarity of the descriptors, contrast-enhanced on the fly "
                            "(scale/streaming_similarity.hpp), fast engine; no N x N matrix held");
    parameters.emplace_back("similarity cells computed during the alignment",
                            fmt::format("{} ({:.2f} x N^2, recomputations included)", run.streamed_cells,
                                        static_cast<double>(run.streamed_cells) / (nn * nn)));
    parameters.emplace_back("tile cache [MB]",
                            fmt::format("{:.1f}", static_cast<double>(run.streamed_cache_bytes) / 1e6));
  }
  if (drawn.block() > 1) {
    parameters.emplace_back("similarity.png", fmt::format("an overview: each pixel the maximum of a block of {0} x {0} "
                                                          "scores, the alignments drawn over it",
                                                          drawn.block()));
  }
  std::string names;
  for (std::size_t k = 0; k < run.descriptor_names.size(); ++k) {
    names += (k ? ", " : "") + run.descriptor_names[k] +
             (k < run.similarities.size() ? fmt::format(" (kappa {:.4g})", run.similarities[k].kappa)
                                          : std::string(" (cosine)"));
  }
  parameters.emplace_back("descriptors", names);
  // The values the run used (the map's decisions: fitted cap and threshold, frames per place applied), not the
  // configured starting points, which the significance statistics and the place scale replace.
  const std::string origin = d.statistics.valid() ? " (fitted)" : "";
  parameters.insert(parameters.end(),
                    {{"contrast enhancement", d.contrast_window > 0 ? fmt::format("window {} frames, offset {:.2f} sd",
                                                                                  d.contrast_window, d.contrast_offset)
                                                                    : "off"},
                     {"gap", fmt::format("{}", c.search.gap)},
                     {"cap", d.cap ? fmt::format("{:.1f}{}", *d.cap, origin) : "none"},
                     {"score a revisit needs", fmt::format("{:.1f}{}", d.score_threshold, origin)},
                     {"min separation [frames]", std::to_string(d.min_separation)},
                     {"reverse pass", c.search.reverse ? "yes" : "no"},
                     {"pruning: min retained fraction", fmt::format("{}", c.labels.pruning.min_retained_fraction)}});
  html.key_values(parameters);

  html.heading("Static figures (the PNG and SVG files, for papers)");
  html.begin_details("similarity.png, pr_curve.png, topology.svg");
  if (run.metrics) {
    html.png("Precision-recall, sweeping the score threshold", read_file(out.staged("pr_curve.png")), "pr_curve.png");
  }
  // Its size first: a large figure is not read back only to be left out.
  const auto similarity_bytes = std::filesystem::file_size(out.staged("similarity.png"));
  if (similarity_bytes <= detail::kMaxInlinedFigure) {
    html.png(what + " (bright = similar) with the alignments: kept pairs red, pruned blue",
             read_file(out.staged("similarity.png")), "similarity.png");
  } else {
    html.paragraph(
        fmt::format("similarity.png ({:.1f} MB) is in the folder beside this report, not inlined: the "
                    "interactive view above shows the same matrix.",
                    static_cast<double>(similarity_bytes) / 1e6));
  }
  html.svg(result.map.places.size() <= kMaxDrawnPlaces
               ? "Places (red: junctions, blue: revisited places) and their connections"
               : "Junctions (red) and path ends joined by path segments, each drawn as a chain of runs of places "
                 "(box label: number of places)",
           read_file(out.staged("topology.svg")), "topology.svg");
  html.end_details();

  // Timings last: the report's own time is measured up to here.
  html.heading("Timings");
  html.raw(
      "<p class=\"note\">Every stage of the run, one after the other: they add up to the wall time. Hover a "
      "part for its share.</p><div id=\"timings-view\"></div><div class=\"readout\" id=\"timings-readout\">"
      "</div>\n");
  auto timings = run.timings;
  data["timings"] = detail::timings_json(timings, options, report_start);
  std::vector<std::vector<std::string>> rows;
  for (const auto& [stage, seconds] : timings) rows.push_back({stage, fmt::format("{:.3f}", seconds)});
  rows.push_back({"wall time", fmt::format("{:.3f}", data["timings"]["wall"].get<double>())});
  html.table({"stage", "seconds"}, rows);
  data["parameters"] = parameters;
  const ReportResult status = detail::finish_interactive(html, data);
  out.write("report.html", html.html());
  return status;
}

}  // namespace seqtopo::outputs
