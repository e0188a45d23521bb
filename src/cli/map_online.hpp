#pragma once
// `seqtopo map INPUT --online` (docs/online.md): the options it reads and the run, kept apart from
// map_command.cpp, which only hands them over.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "seqtopo/pipeline/map_request.hpp"

namespace seqtopo::cli {

struct OnlineCliOptions {
  std::vector<std::string> inputs;
  std::string out, input_kind, ground_truth;
  std::optional<double> gt_radius;
  std::size_t every = 1;
  // The offline map's options --online reads (gap, threshold, cap, e_value, min_separation, contrast window and
  // offset, reverse); the others are refused before this is called.
  pipeline::MapOverrides set;
  std::optional<double> candidate_e_value;  // --candidate-e-value E
  bool no_candidates = false;               // --candidate-e-value none
  bool offline_outputs = true;
  unsigned threads = 0;
};

// --online, --no-offline-outputs and --candidate-e-value on `seqtopo map`.
void add_online_options(CLI::App& app, bool& online, bool& no_offline_outputs, std::optional<double>& candidate_e_value,
                        bool& no_candidates);
void run_map_online(const OnlineCliOptions& options);

}  // namespace seqtopo::cli
