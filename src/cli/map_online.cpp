// seqtopo map --online: frames one at a time, events.jsonl flushed after every frame, a line per event on
// stdout, then the usual outputs of the offline map of the whole sequence beside the online files.
#include "map_online.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/pipeline/online_map.hpp"

namespace seqtopo::cli {
namespace {
namespace fs = std::filesystem;

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, k == 0 ? 0 : k - 1)];
}

// Image paths from stdin, linked under natural-order names so that the offline map reads the same frames.
class LinkFolder {
 public:
  explicit LinkFolder(const std::vector<fs::path>& files)
      : dir_(fs::temp_directory_path() / fmt::format("seqtopo-online-{}", ::getpid())), files_(files) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (std::size_t k = 0; k < files.size(); ++k) {
      links_.push_back(dir_ / fmt::format("{:08d}{}", k, files[k].extension().string()));
      fs::create_symlink(fs::absolute(files[k]), links_.back());
    }
  }
  ~LinkFolder() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  LinkFolder(const LinkFolder&) = delete;
  LinkFolder& operator=(const LinkFolder&) = delete;
  const fs::path& dir() const { return dir_; }
  // An error about the links, about the files they stand for (the user's paths, not the links' names).
  InputError translated(const InputError& e) const {
    const auto original = [&](const std::string& text) {
      // Links (whole paths first, then bare names) become markers, the markers the user's paths: a user's path
      // that looks like a link's name is never replaced again.
      const auto marker = [](std::size_t k) { return fmt::format("\x01{}\x02", k); };
      const auto replace_all = [](std::string& s, const std::string& from, const std::string& to) {
        for (std::size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size()) {
          s.replace(at, from.size(), to);
        }
      };
      std::string out = text;
      for (std::size_t k = 0; k < links_.size(); ++k) replace_all(out, links_[k].string(), marker(k));
      for (std::size_t k = 0; k < links_.size(); ++k) replace_all(out, links_[k].filename().string(), marker(k));
      replace_all(out, dir_.string(), "stdin");
      for (std::size_t k = 0; k < links_.size(); ++k) replace_all(out, marker(k), files_[k].string());
      return out;
    };
    return {original(e.subject()), original(e.what())};
  }

 private:
  fs::path dir_;
  std::vector<fs::path> files_, links_;
};

std::string metrics_json(const evaluation::LoopClosureMetrics& m) {
  return fmt::format(R"({{"precision": {}, "recall": {}, "f1": {}, "auc": {}, "tp": {}, "fp": {}, "fn": {}}})",
                     m.precision, m.recall, m.f1, m.auc, m.tp, m.fp, m.fn);
}

}  // namespace

void add_online_options(CLI::App& app, bool& online, bool& no_offline_outputs, std::optional<double>& candidate_e_value,
                        bool& no_candidates) {
  app.add_flag("--online", online,
               "map while the frames arrive, one at a time in order (image folder, video, descriptors.npy, "
               "similarity.npy, or image paths on stdin with INPUT -): events.jsonl flushed after every frame, a line "
               "per event on stdout, then the offline map's outputs (docs/online.md); --min-separation and "
               "--contrast-window count frames");
  app.add_flag("--no-offline-outputs", no_offline_outputs,
               "with --online: write only the online files (events.jsonl, online_loop_closures.csv, online.json), "
               "not the offline map of the whole sequence");
  add_number_or(app, "--candidate-e-value", candidate_e_value, "none", no_candidates, kPositive,
                fmt::format("with --online: report a revisit candidate, before it is confirmed, once its score "
                            "reaches this E-value (above --e-value), or none (default {}; unused with --e-value none)",
                            *mapping::OnlineMapConfig{}.candidate_e_value));
}

void run_map_online(const OnlineCliOptions& o) {
  if (o.inputs.size() != 1) {
    throw InputError("--online", fmt::format("maps one input (a folder, video, descriptors.npy, similarity.npy or - "
                                             "for image paths on stdin), got {}",
                                             o.inputs.size()));
  }
  pipeline::OnlineMapRequest request;
  const std::string& input = o.inputs.front();
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  request.input = pipeline::SequenceInput(fs::path(input), kind, o.every);
  request.paths = &std::cin;
  auto& c = request.config;
  if (o.gap) c.gap = *o.gap;
  if (o.threshold) c.threshold = *o.threshold;
  if (o.e_value) c.max_e_value = *o.e_value;
  if (o.no_e_value) c.max_e_value.reset();
  if (o.candidate_e_value) c.candidate_e_value = *o.candidate_e_value;
  if (o.no_candidates) c.candidate_e_value.reset();
  if (o.cap) c.cap = *o.cap;
  if (o.no_cap) c.cap.reset();
  if (o.min_separation) c.min_separation = *o.min_separation;
  if (o.contrast_window) c.contrast_window = *o.contrast_window;
  if (o.contrast_offset) c.contrast_offset = *o.contrast_offset;
  c.reverse = !o.no_reverse;
  option_value("--online", [&] {
    mapping::validate(c);
    return 0;
  });
  if (input != "-") pipeline::resolve_input_kind(request.input);  // InputError naming a missing input
  std::vector<fs::path> inputs;
  if (input != "-") inputs.emplace_back(input);
  if (!o.ground_truth.empty()) inputs.emplace_back(o.ground_truth);
  io::OutputDirectory out(o.out, {.inputs = inputs, .command = "seqtopo map --online"});
  const fs::path live = out.staged("events.jsonl");
  std::ofstream events(live);
  if (!events) throw InputError(live.string(), "cannot be written");
  std::map<std::string, std::size_t> counts;
  bool announced = false;
  const auto start = std::chrono::steady_clock::now();
  const pipeline::OnlineMapRun run =
      pipeline::run_online_map(request, [&](std::size_t frame, std::span<const mapping::OnlineEvent> frame_events) {
        for (const auto& e : frame_events) {
          events << pipeline::online_event_json(e) << '\n';
          std::cout << pipeline::online_event_summary(e) << '\n';
          ++counts[std::string(mapping::to_string(e.kind))];
        }
        // Every event of this frame is readable before the next frame is read.
        events.flush();
        std::cout.flush();
        if (!events) throw InputError(live.string(), "write failed");
        // Announced once the first frame is in, so that input refused at once costs one line.
        if (frame == 0 && !announced) {
          announced = true;
          std::cerr << "seqtopo map: events.jsonl is written to " << live.string() << " as the frames arrive (moved to "
                    << o.out << " at the end)\n";
        }
      });
  events.close();
  const double online_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::string closures = "i,j,direction,confidence,revisit\n";
  for (const auto& lc : run.loop_closures) {
    closures += fmt::format("{},{},{},{},{}\n", lc.i, lc.j, align::to_string(lc.direction), lc.confidence, lc.revisit);
  }
  out.write("online_loop_closures.csv", closures);

  std::optional<evaluation::LoopClosureMetrics> metrics, offline_metrics;
  if (!o.ground_truth.empty()) {
    const auto truth = pipeline::load_same_place(o.ground_truth, o.gt_radius, run.frames, o.every);
    const auto has_partner =
        evaluation::images_with_earlier_partner(run.frames, truth.same_place, truth.earlier_partners, c.min_separation);
    metrics = evaluation::evaluate_loop_closures(pipeline::online_scored_pairs(run.loop_closures), has_partner,
                                                 truth.same_place);
  }
  // The offline map of the whole sequence: map.json, figures, report (docs/online.md).
  std::optional<pipeline::MapRun> offline;
  if (o.offline_outputs) {
    std::unique_ptr<LinkFolder> links;
    pipeline::MapRequest map_request;
    map_request.settings.similarity.threads = o.threads;
    map_request.settings.map.threads = std::max(1U, o.threads);
    if (input == "-") {
      links = std::make_unique<LinkFolder>(run.image_files);
      map_request.input = {links->dir(), pipeline::InputKind::images};
    } else {
      map_request.input = request.input;
    }
    map_request.truth.same_place = o.ground_truth;
    map_request.truth.radius = o.gt_radius;
    try {
      const pipeline::MapJob job(map_request);
      offline = job.run();
    } catch (const InputError& e) {
      if (!links) throw;
      throw links->translated(e);
    }
    outputs::write_map_outputs(*offline, out);
    outputs::write_map_report(*offline, out, {});
    offline_metrics = offline->metrics;
  }
  std::string summary = fmt::format(R"({{"frames": {}, "loop_closures": {}, "seconds": {}, "frame_seconds": )",
                                    run.frames, run.loop_closures.size(), online_seconds);
  summary += fmt::format(R"({{"median": {}, "p99": {}, "max": {}}}, "events": {{)", quantile(run.frame_seconds, 0.5),
                         quantile(run.frame_seconds, 0.99), quantile(run.frame_seconds, 1.0));
  bool first = true;
  for (const auto& [name, count] : counts) {
    summary += fmt::format(R"({}"{}": {})", first ? "" : ", ", name, count);
    first = false;
  }
  summary += "}";
  const auto& st = run.statistics;
  summary +=
      fmt::format(R"(, "significance": {{"max_e_value": {}, "threshold": {})",
                  request.config.max_e_value ? fmt::format("{}", *request.config.max_e_value) : "null", run.threshold);
  if (st.valid()) {
    summary += fmt::format(R"(, "lambda": {}, "k": {}, "area": {}, "fitted": {}, "fitted_to": "{}")", st.lambda, st.k,
                           st.area, st.fitted, run.statistics_from_table ? "table" : "islands");
  }
  summary += fmt::format(R"(, "contrast_offset": {}, "offset_changes": [)", run.contrast_offset);
  for (std::size_t k = 0; k < run.offset_changes.size(); ++k) {
    const auto& x = run.offset_changes[k];
    summary += fmt::format(
        R"({}{{"frame": {}, "from": {}, "to": {}, "check": "{}", "global_rate": {}, "chance_length": {}, "bound": {}, )"
        R"("frames_per_place": {}}})",
        k ? ", " : "", x.frame, x.from, x.to, x.check, x.global_rate, x.chance_length, x.bound, x.frames_per_place);
  }
  summary += "]}";
  if (metrics) summary += ", \"metrics\": " + metrics_json(*metrics);
  if (offline_metrics) summary += ", \"offline_metrics\": " + metrics_json(*offline_metrics);
  summary += "}\n";
  out.write("online.json", summary);
  out.commit();
  std::cerr << fmt::format(
      "seqtopo map: {} frames online, {} loop closures, per frame median {:.2f} ms, p99 {:.2f} ms\n", run.frames,
      run.loop_closures.size(), 1e3 * quantile(run.frame_seconds, 0.5), 1e3 * quantile(run.frame_seconds, 0.99));
  for (const auto& warning : run.warnings) std::cerr << "seqtopo map: " << warning << "\n";
  for (const auto& x : run.offset_changes) {
    const std::string why =
        x.check == "scores"
            ? fmt::format("the scores' global alignment rate is {:.3f} a step, above {:.2f} (linear phase)",
                          x.global_rate, request.config.max_global_rate.value_or(0.0F))
            : fmt::format(
                  "chance islands grow with the sequence ({:.1f} places at {:.2f} frames per place, linear "
                  "phase)",
                  x.chance_length, x.frames_per_place);
    std::cerr << fmt::format("seqtopo map: online contrast offset {:.2f}: {}; raised to {:.2f} after frame {}\n",
                             x.from, why, x.to, x.frame);
  }
  if (st.valid()) {
    std::cerr << fmt::format(
        "seqtopo map: online significance: lambda {:.3g}, K {:.3g} (from {} chance {}); at the last frame E <= "
        "{:g} needed a score of {:.3g}\n",
        st.lambda, st.k, st.fitted,
        run.statistics_from_table ? "alignments of the table so far: too few islands yet" : "islands",
        *request.config.max_e_value, run.threshold);
  }
  if (metrics) {
    std::cerr << fmt::format("seqtopo map: online loop closures: precision {:.3f} recall {:.3f} F1 {:.3f}\n",
                             metrics->precision, metrics->recall, metrics->f1);
  }
  if (offline_metrics) {
    std::cerr << fmt::format("seqtopo map: offline loop closures: precision {:.3f} recall {:.3f} F1 {:.3f}\n",
                             offline_metrics->precision, offline_metrics->recall, offline_metrics->f1);
  }
}

}  // namespace seqtopo::cli
