// seqtopo command line: dispatches to the registered subcommands and turns every failure into one line
// `seqtopo: error: <file or option>: <what is wrong>` and a non-zero exit.
#include <algorithm>
#include <fstream>
#include <iostream>
#include <thread>

#include "command_registry.hpp"
#include "number_options.hpp"
#include "seqtopo/core/input_error.hpp"

namespace seqtopo::cli {

std::vector<CommandSpec>& command_registry() {
  static std::vector<CommandSpec> registry;
  return registry;
}

unsigned resolve_threads(unsigned requested) {
  const unsigned cores = std::max(1U, std::thread::hardware_concurrency());
  return requested > 0 ? std::min(requested, cores) : cores;
}

namespace {

// `--config FILE` becomes the options it lists, placed before the command line's own options so that
// those win (every option takes its last value). FILE holds `name: value` lines; `#` starts a comment;
// `name: true` is a flag.
std::vector<std::string> expand_config(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  std::vector<std::string> from_file;
  std::size_t insert_at = std::string::npos;
  for (std::size_t k = 0; k < args.size(); ++k) {
    std::string path;
    if (args[k] == "--config" && k + 1 < args.size()) {
      path = args[++k];
    } else if (args[k].rfind("--config=", 0) == 0) {
      path = args[k].substr(9);
    } else {
      out.push_back(args[k]);
      continue;
    }
    if (insert_at == std::string::npos) insert_at = out.size();
    std::ifstream in(path);
    if (!in) throw seqtopo::InputError(path, "cannot open config file");
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
      const auto trim = [](std::string t) {
        t.erase(0, t.find_first_not_of(" \t\r"));
        t.erase(t.find_last_not_of(" \t\r") + 1);
        return t;
      };
      line = trim(line);
      if (line.empty() || line == "---") continue;
      const auto colon = line.find(':');
      if (colon == std::string::npos) {
        throw seqtopo::InputError(path + ":" + std::to_string(line_no), "expected `name: value`, got '" + line + "'");
      }
      const std::string name = trim(line.substr(0, colon));
      std::string value = trim(line.substr(colon + 1));
      if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front()) {
        value = value.substr(1, value.size() - 2);
      }
      if (value == "true") {
        from_file.push_back("--" + name);
      } else if (value != "false") {
        from_file.push_back("--" + name);
        from_file.push_back(value);
      }
    }
  }
  if (insert_at != std::string::npos) {
    // after the program name and the subcommand: the options of the file go first
    const std::size_t at = std::min(out.size(), std::max<std::size_t>(insert_at, 2));
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), from_file.begin(), from_file.end());
  }
  return out;
}

}  // namespace

}  // namespace seqtopo::cli

int main(int argc, char** argv) {
  // Named, so that --help says "Usage: seqtopo [OPTIONS] SUBCOMMAND" (and "seqtopo map [OPTIONS] ...").
  CLI::App app{"seqtopo: topological mapping and localization of a mobile robot with sequence alignment", "seqtopo"};
  app.require_subcommand(1);
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.set_version_flag("--version", "seqtopo 0.1.0");
  auto commands = seqtopo::cli::command_registry();
  std::sort(commands.begin(), commands.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& command : commands) command.setup(*app.add_subcommand(command.name, command.description));
  seqtopo::cli::check_all_numeric_options(app);

  try {
    std::vector<std::string> args(argv, argv + argc);
    args = seqtopo::cli::expand_config(args);
    // CLI11 parses a reversed vector of the arguments after the program name.
    std::vector<std::string> reversed(args.rbegin(), args.rend() - 1);
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Point to the help of the subcommand that was being parsed ("seqtopo map --help").
    std::string help = "seqtopo";
    for (const CLI::App* sub = &app; sub != nullptr;) {
      const auto parsed = sub->get_subcommands();
      sub = parsed.empty() ? nullptr : parsed.front();
      if (sub) help += " " + sub->get_name();
    }
    std::cerr << "seqtopo: error: " << e.what() << " (see " << help << " --help)\n";
    return 2;
  } catch (const seqtopo::InputError& e) {
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
