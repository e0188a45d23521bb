// seqtopo command line: dispatches to the registered subcommands and turns every failure into one line
// `seqtopo: error: <file or option>: <what is wrong>` and a non-zero exit.
#include <algorithm>
#include <iostream>
#include <thread>

#include "command_registry.hpp"
#include "seqtopo/io/input_error.hpp"

namespace seqtopo::cli {

std::vector<CommandSpec>& command_registry() {
  static std::vector<CommandSpec> registry;
  return registry;
}

unsigned resolve_threads(unsigned requested) {
  if (requested > 0) return requested;
  return std::max(1U, std::thread::hardware_concurrency());
}

}  // namespace seqtopo::cli

int main(int argc, char** argv) {
  CLI::App app{"seqtopo: topological mapping and localization of a mobile robot with sequence alignment"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "seqtopo 0.1.0");
  auto commands = seqtopo::cli::command_registry();
  std::sort(commands.begin(), commands.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& command : commands) command.setup(*app.add_subcommand(command.name, command.description));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "seqtopo: error: " << e.what() << " (see seqtopo --help)\n";
    return 2;
  } catch (const seqtopo::io::InputError& e) {
    std::cerr << "seqtopo: error: " << e.subject() << ": " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "seqtopo: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "seqtopo: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
