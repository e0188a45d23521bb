#pragma once
// Running the seqtopo command line from a test (SEQTOPO_CLI is the binary's path, set by CMake).
#include <optional>
#include <string>

#include "common/run_command.hpp"

namespace seqtopo::test_support {

// `seqtopo ARGS` (split into words by the shell) with `input` on its stdin (none: /dev/null, never the
// terminal): its exit status (-1 if it did not exit, e.g. a crash), stdout and stderr.
inline CommandResult run_cli(const std::string& args, const std::optional<std::string>& input = std::nullopt) {
  return run_command("exec " + std::string(SEQTOPO_CLI) + " " + args, input);
}

}  // namespace seqtopo::test_support
