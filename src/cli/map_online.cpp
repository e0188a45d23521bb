// seqtopo map --online: frames one at a time, events.jsonl flushed after every frame, a line per event on
// stdout, then the usual outputs of the offline map of the whole sequence beside the online files.
#include "map_online.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/decision_notes.hpp"
#include "seqtopo/formats/online_events.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/online_outputs.hpp"
#include "seqtopo/pipeline/online_map.hpp"

namespace seqtopo::cli {
namespace {
namespace fs = std::filesystem;
}  // namespace

void add_online_options(CLI::App& app, bool& online, bool& no_offline_outputs, std::optional<double>& candidate_e_value,
                        bool& no_candidates) {
  app.add_flag("--online", online,
               "map while the frames arrive, one at a time in order (image folders, videos, descriptors.npy, one "
               "similarity.npy, or image paths on stdin with INPUT -; several inputs are the sessions of one map): "
               "events.jsonl flushed after every frame, a line per event on stdout, then the offline map's outputs "
               "(docs/online.md); --min-separation and --contrast-window count frames, or places with "
               "--frames-per-place F");
  app.add_flag("--no-offline-outputs", no_offline_outputs,
               "with --online: write only the online files (events.jsonl, online_loop_closures.csv, online.json), "
               "not the offline map of the whole sequence");
  add_number_or(app, "--candidate-e-value", candidate_e_value, "none", no_candidates, kPositive,
                fmt::format("with --online: report a revisit candidate, before it is confirmed, once its score "
                            "reaches this E-value (above --e-value), or none (default {}; unused with --e-value none)",
                            *mapping::OnlineMapConfig{}.candidate_e_value));
}

void run_map_online(const OnlineCliOptions& o) {
  pipeline::OnlineMapRequest request;
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  for (const auto& input : o.inputs) request.sessions.emplace_back(fs::path(input), kind, o.every);
  request.paths = &std::cin;
  auto& c = request.config;
  pipeline::apply_overrides(c, o.set);
  if (o.candidate_e_value) c.candidate_e_value = *o.candidate_e_value;
  if (o.no_candidates) c.candidate_e_value.reset();
  option_value("--online", [&] {
    mapping::validate(c);
    return 0;
  });
  std::vector<fs::path> inputs;
  for (const auto& session : request.sessions) {
    if (session.path == "-") continue;
    pipeline::resolve_input_kind(session);  // InputError naming a missing input
    inputs.push_back(session.path);
  }
  if (!o.ground_truth.empty()) inputs.emplace_back(o.ground_truth);
  io::OutputDirectory out(o.out, {.inputs = inputs, .command = "seqtopo map --online"});
  const fs::path live = out.staged("events.jsonl");
  std::ofstream events(live);
  if (!events) throw InputError(live.string(), "cannot be written");
  bool announced = false;
  request.truth.same_place = o.ground_truth;
  request.truth.radius = o.gt_radius;
  request.offline_map = o.offline_outputs;
  request.threads = o.threads;
  const pipeline::OnlineMapRun run =
      pipeline::run_online_map(request, [&](std::size_t frame, std::span<const mapping::OnlineEvent> frame_events) {
        for (const auto& e : frame_events) {
          events << formats::online_event_json(e) << '\n';
          std::cout << formats::online_event_summary(e) << '\n';
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
  outputs::write_online_map_outputs(run, request.config, out);
  out.commit();
  const auto& st = run.statistics;
  const auto& metrics = run.metrics;
  const evaluation::LoopClosureMetrics* offline_metrics =
      run.offline && run.offline->metrics ? &*run.offline->metrics : nullptr;
  std::cerr << fmt::format(
      "seqtopo map: {} frames online, {} loop closures, per frame median {:.2f} ms, p99 {:.2f} ms\n", run.frames,
      run.loop_closures.size(), 1e3 * outputs::quantile(run.frame_seconds, 0.5),
      1e3 * outputs::quantile(run.frame_seconds, 0.99));
  for (const auto& warning : run.warnings) std::cerr << "seqtopo map: " << warning << "\n";
  for (const auto& x : run.offset_changes) {
    const std::string why =
        x.check == "scores"
            ? fmt::format("the scores' global alignment rate is {:.3f} a step, above {:.2f} (linear phase)",
                          x.global_rate, request.config.phase.max_global_rate.value_or(0.0F))
            : fmt::format(
                  "chance islands grow with the sequence ({:.1f} places at {:.2f} frames per place, linear "
                  "phase)",
                  x.chance_length, x.frames_per_place);
    std::cerr << fmt::format("seqtopo map: online contrast offset {:.2f}: {}; raised to {:.2f} after frame {}\n",
                             x.from, why, x.to, x.frame);
  }
  if (!run.low_information_frames.empty()) {
    const std::size_t stretches = formats::frame_stretches(run.low_information_frames).size();
    std::cerr << fmt::format(
        "seqtopo map: online: {} image{} of little information (dark or near-uniform) in {} stretch{}: no evidence "
        "of a revisit (soft-masked)\n",
        run.low_information_frames.size(), run.low_information_frames.size() == 1 ? "" : "s", stretches,
        stretches == 1 ? "" : "es");
  }
  if (st.valid()) {
    std::cerr << fmt::format(
        "seqtopo map: online significance: lambda {:.3g}, K {:.3g} (from {} chance {}); at the last frame E <= "
        "{:g} needed a score of {:.3g}\n",
        st.lambda, st.k, st.fitted,
        run.statistics_from_table ? "alignments of the table so far: too few islands yet" : "islands",
        *request.config.significance.max_e_value, run.threshold);
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
