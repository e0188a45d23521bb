// `seqtopo bench <what>`: measurements a user can repeat on their own machine. Each kind of benchmark is
// its own file registering with RegisterBenchCommand; this file only gathers them under `bench`.
#include <algorithm>

#include "command_registry.hpp"

namespace seqtopo::cli {

std::vector<CommandSpec>& bench_registry() {
  static std::vector<CommandSpec> registry;
  return registry;
}

namespace bench_command {
namespace {

void setup(CLI::App& bench) {
  auto specs = bench_registry();
  std::sort(specs.begin(), specs.end(), [](const CommandSpec& a, const CommandSpec& b) { return a.name < b.name; });
  for (const auto& spec : specs) spec.setup(*bench.add_subcommand(spec.name, spec.description));
  bench.require_subcommand(1);
}

const RegisterCommand registered{{"bench", "Measure speed and memory of the engine and the pipeline", setup}};

}  // namespace
}  // namespace bench_command
}  // namespace seqtopo::cli
