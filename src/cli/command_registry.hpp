#pragma once
// Subcommands register themselves here (one source file each under src/cli/), so adding a command
// touches only its own file.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace seqtopo::cli {

struct CommandSpec {
  std::string name;
  std::string description;
  // Adds the options to the subcommand and sets its callback.
  std::function<void(CLI::App&)> setup;
};

std::vector<CommandSpec>& command_registry();

struct RegisterCommand {
  explicit RegisterCommand(CommandSpec spec) { command_registry().push_back(std::move(spec)); }
};

// Number of worker threads to use: `requested`, or every core when 0.
unsigned resolve_threads(unsigned requested);

}  // namespace seqtopo::cli
