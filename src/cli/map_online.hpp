#pragma once
// `seqtopo map INPUT --online` (docs/online.md): the options it reads and the run, kept apart from
// map_command.cpp, which only hands them over.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace seqtopo::cli {

struct OnlineCliOptions {
  std::vector<std::string> inputs;
  std::string out, input_kind, ground_truth;
  std::size_t every = 1;
  std::optional<float> gap, threshold, cap, contrast_offset;
  bool no_cap = false, no_reverse = false;
  std::optional<std::size_t> min_separation, contrast_window;
  std::optional<double> gt_radius;
  bool offline_outputs = true;
  unsigned threads = 0;
  std::optional<double> e_value;            // --e-value E
  bool no_e_value = false;                  // --e-value none
  std::optional<double> candidate_e_value;  // --candidate-e-value E
  bool no_candidates = false;               // --candidate-e-value none
};

// --online, --no-offline-outputs and --candidate-e-value on `seqtopo map`.
void add_online_options(CLI::App& app, bool& online, bool& no_offline_outputs, std::optional<double>& candidate_e_value,
                        bool& no_candidates);
void run_map_online(const OnlineCliOptions& options);

}  // namespace seqtopo::cli
