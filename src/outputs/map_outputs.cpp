#include "seqtopo/outputs/map_outputs.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "figures.hpp"
#include "report_data.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/formats/map_json.hpp"
#include "seqtopo/formats/pose_files.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/plot/pr_curve.hpp"
#include "seqtopo/plot/trajectory_map.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs {
namespace {

// The Graphviz text of the map's drawing and the number of nodes it draws.
struct TopologyDrawing {
  std::string dot;
  std::size_t nodes = 0;
};

TopologyDrawing topology_dot(const mapping::TopologicalMap& map) {
  std::size_t nodes = 0;
  std::ostringstream dot;
  dot << "graph topology {\n  graph [overlap=false, splines=false];\n  node [shape=circle, width=0.25, fixedsize=true, "
         "fontsize=8, style=filled, fillcolor=\"#dddddd\"];\n";
  std::vector<bool> junction(map.places.size(), false);
  for (auto j : map.junctions) junction[j] = true;
  // The edges that leave a junction, each branch in its own colour, so the branching is seen at a glance.
  const auto branch_style = [&](mapping::PlaceLabel p, mapping::PlaceLabel q) -> std::string {
    static constexpr const char* kColours[] = {"#e41a1c", "#ff7f00", "#4daf4a", "#984ea3", "#a65628", "#f781bf"};
    for (const auto& j : map.junction_evidence) {
      for (std::size_t b = 0; b < j.branches.size(); ++b) {
        if ((j.place == p && j.branches[b] == q) || (j.place == q && j.branches[b] == p))
          return fmt::format(" [penwidth=3, color=\"{}\"]", kColours[b % std::size(kColours)]);
      }
    }
    return "";
  };
  auto node = [&](const mapping::Place& place) {
    ++nodes;
    dot << "  p" << place.id << " [label=\"" << place.id << "\", tooltip=\"images";
    for (std::size_t k = 0; k < place.images.size() && k < 12; ++k) dot << ' ' << place.images[k];
    dot << "\"";
    if (junction[place.id]) {
      // A junction stands out: a larger red double circle named J<place>, its branches listed in the tooltip.
      dot << ", shape=doublecircle, fillcolor=\"#e41a1c\", fontcolor=white, width=0.5, fontsize=9, xlabel=\"J"
          << place.id << "\"";
    } else if (place.images.size() > 1) {
      dot << ", fillcolor=\"#377eb8\", fontcolor=white";
    }
    dot << "];\n";
  };
  if (map.places.size() <= kMaxDrawnPlaces) {
    for (const auto& place : map.places) node(place);
    for (auto [p, q] : map.edges) dot << "  p" << p << " -- p" << q << branch_style(p, q) << ";\n";
  } else {
    // Each segment's inner places as a chain of at most 8 runs (node label: its number of places), so that the
    // picture keeps the segment's shape: a loop is drawn as a ring, not as one edge from a node to itself.
    std::vector<bool> drawn(map.places.size(), false);
    for (std::size_t k = 0; k < map.segments.size(); ++k) {
      const auto& s = map.segments[k];
      for (auto end : {s.places.front(), s.places.back()}) {
        if (!drawn[end]) node(map.places[end]);
        drawn[end] = true;
      }
      const std::size_t inner = s.places.size() > 2 ? s.places.size() - 2 : 0, runs = std::min<std::size_t>(8, inner);
      std::string previous = fmt::format("p{}", s.places.front());
      for (std::size_t r = 0; r < runs; ++r) {
        const std::size_t begin = 1 + r * inner / runs, end = 1 + (r + 1) * inner / runs;
        const std::string run = fmt::format("s{}r{}", k, r);
        ++nodes;
        dot << "  " << run << " [label=\"" << end - begin << "\", shape=box, width=0.3, height=0.2, fontsize=7, "
            << "fillcolor=\"#9ecae1\", tooltip=\"places " << s.places[begin] << " to " << s.places[end - 1] << "\"];\n";
        dot << "  " << previous << " -- " << run << ";\n";
        previous = run;
      }
      dot << "  " << previous << " -- p" << s.places.back() << ";\n";
    }
  }
  dot << "}\n";
  return {dot.str(), nodes};
}

// Above this many drawn nodes no Graphviz layout finishes in minutes (the 10^6-frame route draws some 10^5),
// so the picture is a note instead; topology.dot still holds the drawing for a user's own tools.
constexpr std::size_t kMaxLaidOutNodes = 10'000;

std::string unlaid_topology_svg(const mapping::TopologicalMap& map, std::size_t nodes) {
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"720\" height=\"80\">\n"
      "  <text x=\"10\" y=\"30\" font-family=\"sans-serif\" font-size=\"14\">{} places, {} segments, {} junctions: "
      "the drawing has {} nodes, more than {} can be laid out.</text>\n"
      "  <text x=\"10\" y=\"55\" font-family=\"sans-serif\" font-size=\"14\">topology.dot holds it; map.json "
      "every place.</text>\n</svg>\n",
      map.places.size(), map.segments.size(), map.junctions.size(), nodes, kMaxLaidOutNodes);
}

// Runs Graphviz on a staged .dot file to make the .svg beside it. Edges are straight: neato's spline
// routing takes minutes on a few hundred tangled places. The layout is bounded in time, so a map is never
// held up by its picture: neato, else sfdp, which is fast at any size; sfdp alone past kNeatoNodes drawn nodes,
// where it draws as well in a fraction of the time (2,627 nodes: 2 s against neato's 14 s).
constexpr std::size_t kNeatoNodes = 1000;

void render_svg(const std::filesystem::path& dot_file, const std::filesystem::path& svg_file, std::size_t nodes) {
  const std::string files = " -Tsvg '" + dot_file.string() + "' -o '" + svg_file.string() + "' 2>/dev/null";
  for (const char* layout : {"timeout 60 dot -Kneato", "timeout 120 dot -Ksfdp"}) {
    if (nodes > kNeatoNodes && std::string_view(layout).find("neato") != std::string_view::npos) continue;
    if (std::system((std::string(layout) + files).c_str()) == 0) return;
  }
  throw InputError("topology.svg", "Graphviz 'dot' failed or is missing (scripts/setup.sh installs graphviz)");
}

// Alignments in the coordinates of the drawn matrix: the scores themselves (block 1) or an overview of
// block x block cells per pixel (--streaming).
std::vector<plot::Polyline> alignment_overlays(const pipeline::MapRun& run, std::size_t block) {
  const auto at = [block](std::size_t i, std::size_t j) {
    return std::pair{plot::overview_coordinate(static_cast<double>(i), block),
                     plot::overview_coordinate(static_cast<double>(j), block)};
  };
  std::vector<plot::Polyline> lines;
  const auto& alignments = run.result.alignments;
  const auto& pruning = run.result.pruning;
  // Pruned parts first (blue), then the retained pairs (red) over them, as in the paper's Fig. 2.
  for (const auto& a : alignments) {
    plot::Polyline line;
    line.rgb = {40, 110, 255};
    line.thickness = 2;
    for (auto [i, j] : a.pairs) line.points.push_back(at(i, j));
    lines.push_back(std::move(line));
  }
  plot::Polyline current;
  std::size_t current_alignment = static_cast<std::size_t>(-1);
  std::size_t previous_i = 0;
  for (const auto& p : pruning.pairs) {
    // break the red line where pruning removed pairs inside a kept alignment
    if (p.alignment != current_alignment || p.i > previous_i + 3) {
      if (!current.points.empty()) lines.push_back(current);
      current = {};
      current.rgb = {255, 30, 30};
      current.thickness = 2;
      current_alignment = p.alignment;
    }
    current.points.push_back(at(p.i, p.j));
    previous_i = p.i;
  }
  if (!current.points.empty()) lines.push_back(current);
  return lines;
}

// With ground truth, where the map is wrong, over the alignments: a hollow square around each false positive
// (magenta) and each missed revisit at its nearest true pair (yellow), a few cells wide so that one stands out on a
// large matrix.
std::vector<plot::Polyline> error_overlays(const pipeline::MapRun& run, std::size_t block) {
  std::vector<plot::Polyline> marks;
  if (!run.errors) return marks;
  const double n = static_cast<double>(run.result.map.labels.size());
  const double half = std::max(1.5, n / 120.0);
  const auto square = [&](std::size_t i, std::size_t j, std::array<std::uint8_t, 3> rgb) {
    plot::Polyline line;
    line.rgb = rgb;
    line.thickness = 2;
    const double r = static_cast<double>(i) + 0.5, c = static_cast<double>(j) + 0.5;
    for (auto [dr, dc] : {std::pair{-1, -1}, std::pair{-1, 1}, std::pair{1, 1}, std::pair{1, -1}, std::pair{-1, -1}}) {
      line.points.emplace_back(plot::overview_coordinate(r + dr * half, block),
                               plot::overview_coordinate(c + dc * half, block));
    }
    marks.push_back(std::move(line));
  };
  for (const auto& m : run.errors->missed) {
    if (m.partner != m.i) square(m.i, m.partner, kMissedColour);
  }
  for (const auto& p : run.errors->false_positives) square(p.i, p.j, kFalsePositiveColour);
  return marks;
}

// The PNG figures of a run: pure computation on the run, so they may be encoded beside the file writes.
struct MapFigures {
  std::string similarity, metric_map, pr_curve;  // empty: not drawn
};

MapFigures encode_map_figures(const pipeline::MapRun& run) {
  MapFigures f;
  const auto& result = run.result;
  {
    // The picture shows what was aligned: S itself, or its contrast-enhanced form (see the report).
    const DrawnMatrix drawn(run);
    auto overlays = alignment_overlays(run, drawn.block());
    const auto errors = error_overlays(run, drawn.block());
    overlays.insert(overlays.end(), errors.begin(), errors.end());
    f.similarity =
        plot::encode_png(plot::matrix_figure(drawn.cells(), overlays, map_similarity_figure(run, drawn.block())));
  }
  if (!run.odometry.empty()) {
    std::vector<std::pair<std::size_t, std::size_t>> loops;
    for (const auto& p : result.pruning.pairs) loops.emplace_back(p.i, p.j);
    std::vector<plot::TrajectoryPanel> panels{{"(a) cumulative odometry", run.odometry}};
    if (run.paper_trajectory) {
      panels.push_back({"(b) topological map with odometry (EKF)", run.ekf});
    } else {
      panels.push_back({"(b) topological map with odometry (pose graph)", run.pose_graph});
    }
    f.metric_map = plot::encode_png(plot::trajectory_map_image(panels, result.map.labels, loops));
  }
  if (run.metrics) {
    std::vector<plot::Curve> curves(run.baseline_metrics ? 2 : 1);
    curves[0].label = "seqtopo alignment";
    curves[0].rgb = {220, 30, 30};
    for (const auto& p : run.metrics->curve) curves[0].recall_precision.emplace_back(p.recall, p.precision);
    if (run.baseline_metrics) {
      curves[1].label = "SeqSLAM-style baseline";
      curves[1].rgb = {40, 90, 220};
      for (const auto& p : run.baseline_metrics->curve) curves[1].recall_precision.emplace_back(p.recall, p.precision);
    }
    f.pr_curve = plot::encode_png(plot::pr_curve_image(curves));
  }
  return f;
}

}  // namespace

bool writes_matrices(std::size_t images, std::optional<bool> asked) {
  return asked.value_or(images <= kMaxAutoMatrixImages);
}

void write_map_outputs(const pipeline::MapRun& run, io::OutputDirectory& out, const MapOutputOptions& options) {
  const auto& result = run.result;
  const auto& map = result.map;
  // The figures (PNG encoding of a large matrix is a good part of this stage) are drawn on a second thread while
  // the files are written, unless the run has one thread; their bytes are the same either way.
  auto figures = std::async(run.map_config.threads > 1 ? std::launch::async : std::launch::deferred,
                            [&run] { return encode_map_figures(run); });

  out.write("map.json", formats::map_json(result, run.map_sessions()));
  out.write("alignments.json", formats::alignments_json(result, run.descriptor_names));
  out.write("loop_closures.csv", formats::loop_closures_csv(result));
  if (!run.streamed() && writes_matrices(map.labels.size(), options.matrices)) {
    out.write_pieces("similarity.npy", {io::npy_header(run.matrices.front()), io::npy_body(run.matrices.front())});
    out.write_pieces("scores.npy", {io::npy_header(result.scores), io::npy_body(result.scores)});
  }

  const TopologyDrawing topology = topology_dot(map);
  out.write("topology.dot", topology.dot);
  if (topology.nodes <= kMaxLaidOutNodes) {
    render_svg(out.staged("topology.dot"), out.staged("topology.svg"), topology.nodes);
  } else {
    out.write("topology.svg", unlaid_topology_svg(map, topology.nodes));
  }

  // The corrected trajectory for a SLAM back end or evo: the pose graph's (the EKF's with the paper preset), one
  // pose per image; TUM's time is the image index.
  if (!run.odometry.empty()) {
    const auto& corrected = run.paper_trajectory ? run.ekf : run.pose_graph;
    std::vector<double> times(corrected.size());
    for (std::size_t k = 0; k < times.size(); ++k) times[k] = static_cast<double>(k);
    out.write("trajectory_tum.txt", formats::tum_text(corrected, times));
    out.write("trajectory_kitti.txt", formats::kitti_text(corrected));
  }

  const MapFigures f = figures.get();
  out.write("similarity.png", f.similarity);
  if (!f.metric_map.empty()) out.write("metric_map.png", f.metric_map);
  if (!f.pr_curve.empty()) out.write("pr_curve.png", f.pr_curve);

  if (run.metrics || run.ate || run.topology) {
    nlohmann::json metrics = {{"seqtopo_version", std::string(version())}};
    if (run.streamed()) metrics["streaming"] = true;
    if (run.metrics) {
      metrics["loop_closure"] = detail::loop_closure_metrics_json(*run.metrics);
      if (run.baseline_metrics) {
        metrics["baseline"] = detail::loop_closure_metrics_json(*run.baseline_metrics);
        metrics["baseline"]["method"] = run.baseline_name;
      } else {
        metrics["baseline_skipped"] = run.baseline_skipped;
      }
      nlohmann::json curve = nlohmann::json::array();
      for (const auto& p : run.metrics->curve)
        curve.push_back({{"threshold", p.threshold}, {"precision", p.precision}, {"recall", p.recall}});
      metrics["loop_closure"]["pr_curve"] = curve;
      metrics["loop_closure"]["ranked_by"] = "confidence";
      if (run.calibration) metrics["loop_closure"]["calibration"] = detail::calibration_json(*run.calibration, "pairs");
    }
    if (run.topology) {
      const auto& t = *run.topology;
      metrics["topology"] = {{"adjusted_rand_index", t.adjusted_rand_index},
                             {"adjusted_rand_index_frames", t.adjusted_rand_index_frames},
                             {"false_merges", t.false_merges},
                             {"missed_merges", t.missed_merges},
                             {"junctions_true", t.junctions_true},
                             {"junctions_found", t.junctions_found},
                             {"junctions_matched", t.junctions_matched}};
    }
    if (run.ate) {
      metrics["metric"] = {
          {"ate_odometry", run.ate->odometry}, {"ate_ekf", run.ate->ekf}, {"ate_pose_graph", run.ate->pose_graph}};
    }
    out.write("metrics.json", metrics.dump(1) + "\n");
  }
}

}  // namespace seqtopo::outputs
