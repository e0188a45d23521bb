#include "seqtopo/outputs/online_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "report_data.hpp"
#include "seqtopo/formats/json_number.hpp"
#include "seqtopo/outputs/map_outputs.hpp"

namespace seqtopo::outputs {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, k == 0 ? 0 : k - 1)];
}

void write_online_map_outputs(const pipeline::OnlineMapRun& run, const mapping::OnlineMapConfig& config,
                              io::OutputDirectory& out) {
  std::string closures = "i,j,direction,confidence,revisit\n";
  for (const auto& lc : run.loop_closures) {
    closures += fmt::format("{},{},{},{},{}\n", lc.i, lc.j, align::to_string(lc.direction), lc.confidence, lc.revisit);
  }
  out.write("online_loop_closures.csv", closures);
  if (run.offline) {
    write_map_outputs(*run.offline, out);
    write_map_report(*run.offline, out, {});
  }
  nlohmann::ordered_json summary = {{"frames", run.frames},
                                    {"loop_closures", run.loop_closures.size()},
                                    {"seconds", run.seconds},
                                    {"frame_seconds",
                                     {{"median", quantile(run.frame_seconds, 0.5)},
                                      {"p99", quantile(run.frame_seconds, 0.99)},
                                      {"max", quantile(run.frame_seconds, 1.0)}}},
                                    {"events", run.event_counts}};
  if (run.sessions.size() > 1) {  // as map.json: the frames [begin, end) of each input
    auto& sessions = summary["sessions"] = nlohmann::ordered_json::array();
    for (const auto& x : run.sessions) sessions.push_back({{"input", x.input}, {"begin", x.begin}, {"end", x.end}});
  }
  nlohmann::ordered_json significance = {
      {"max_e_value", config.significance.max_e_value ? nlohmann::ordered_json(*config.significance.max_e_value)
                                                      : nlohmann::ordered_json()},
      {"threshold", formats::json_number(run.threshold)}};
  const auto& st = run.statistics;
  if (st.valid()) {
    significance["lambda"] = st.lambda;
    significance["k"] = st.k;
    significance["area"] = st.area;
    significance["fitted"] = st.fitted;
    significance["fitted_to"] = run.statistics_from_table ? "table" : "islands";
  }
  significance["contrast_offset"] = formats::json_number(run.contrast_offset);
  auto& changes = significance["offset_changes"] = nlohmann::ordered_json::array();
  for (const auto& x : run.offset_changes) {
    changes.push_back({{"frame", x.frame},
                       {"from", formats::json_number(x.from)},
                       {"to", formats::json_number(x.to)},
                       {"check", x.check},
                       {"global_rate", x.global_rate},
                       {"chance_length", x.chance_length},
                       {"bound", x.bound},
                       {"frames_per_place", x.frames_per_place}});
  }
  // As alignments.json: the images of little information, 0-based, sorted (absent when none).
  if (!run.low_information_frames.empty()) significance["low_information_frames"] = run.low_information_frames;
  summary["significance"] = std::move(significance);
  if (run.metrics) summary["metrics"] = detail::loop_closure_metrics_json(*run.metrics);
  if (run.offline && run.offline->metrics) {
    summary["offline_metrics"] = detail::loop_closure_metrics_json(*run.offline->metrics);
  }
  out.write("online.json", summary.dump(2) + "\n");
}

}  // namespace seqtopo::outputs
