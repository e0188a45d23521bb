#pragma once
// Subcommands register themselves here (one source file each under src/cli/), so adding a command
// touches only its own file.
#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "seqtopo/core/input_error.hpp"

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

// Subcommands of `seqtopo bench` (bench_command.cpp), registered the same way: one file each.
std::vector<CommandSpec>& bench_registry();

struct RegisterBenchCommand {
  explicit RegisterBenchCommand(CommandSpec spec) { bench_registry().push_back(std::move(spec)); }
};

// Runs parse(); a std::invalid_argument from it becomes an InputError naming the option.
template <typename F>
auto option_value(const char* option, F&& parse) {
  try {
    return parse();
  } catch (const std::invalid_argument& e) {
    throw InputError(option, e.what());
  }
}

// Number of worker threads to use: `requested`, or every core when 0; never more than the cores (results do not
// depend on the thread count, and more threads than cores only cost time).
unsigned resolve_threads(unsigned requested);

// The command line as the user typed it (`seqtopo map data --gap 2`), each argument quoted for a POSIX shell where
// it needs it, so that the report's copy can be pasted back. Set once by main().
const std::string& command_line();
void record_command_line(int argc, char** argv);

}  // namespace seqtopo::cli
