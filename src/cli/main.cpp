// seqtopo command line: dispatches to the registered subcommands and turns every failure into one line
// `seqtopo: error: <file or option>: <what is wrong>` and a non-zero exit.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string_view>
#include <thread>

#include "command_registry.hpp"
#include "config_file.hpp"
#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/io/atomic_output.hpp"

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

std::string& recorded_command_line() {
  static std::string text;
  return text;
}

// A POSIX shell word: as it is when it has no character the shell treats specially, else in single quotes.
std::string shell_quoted(std::string_view word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || std::string_view("_-./=:,+@%").find(static_cast<char>(c)) != std::string_view::npos;
  });
  if (plain) return std::string(word);
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

const std::string& command_line() { return recorded_command_line(); }

void record_command_line(int argc, char** argv) {
  std::string text = "seqtopo";  // the program, whatever path started it (the launcher, a venv's entry point)
  for (int k = 1; k < argc; ++k) text += " " + shell_quoted(argv[k]);
  recorded_command_line() = std::move(text);
}

namespace {

// The subcommand the command line runs ("map", or "scale" of "bench scale"), and where its own arguments
// start in `args` (after the program name and the subcommand names).
std::pair<CLI::App*, std::size_t> target_command(CLI::App& app, const std::vector<std::string>& args) {
  CLI::App* command = &app;
  std::size_t k = 1;
  while (k < args.size()) {
    const auto subs = command->get_subcommands([&](CLI::App* sub) { return sub->check_name(args[k]); });
    if (subs.empty()) break;
    CLI::App* sub = subs.front();
    command = sub;
    ++k;
  }
  return {command, k};
}

std::string command_path(const CLI::App* command) {
  std::string path;
  for (const CLI::App* c = command; c != nullptr && c->get_parent() != nullptr; c = c->get_parent()) {
    path = " " + c->get_name() + path;
  }
  return "seqtopo" + path;
}

// The options one config file lists, checked against `command`'s options: every name must be one of its
// long options (without the dashes), a flag takes true or false, a number is checked as on the command line.
// Errors name the file and line (the file as a whole when it is a folder, unreadable, or JSON).
std::vector<std::string> read_config(const std::string& path, CLI::App& command) {
  const std::string text = seqtopo::read_text_file(path, "config file");
  const std::string help = " (see " + command_path(&command) + " --help)";
  std::vector<std::string> options;
  for (const auto& entry : parse_config(text, path)) {
    const std::string where = path + ":" + std::to_string(entry.line);
    const std::string& name = entry.name;
    const std::string& value = entry.value;
    if (name == "config") throw seqtopo::InputError(where, "a config file cannot name another config file");
    CLI::Option* option = name.empty() || name[0] == '-' ? nullptr : command.get_option_no_throw("--" + name);
    if (option == nullptr) {
      throw seqtopo::InputError(where, "unknown option '" + name + "' for " + command_path(&command) +
                                           " (names are long options without the dashes)" + help);
    }
    if (option->get_items_expected_max() == 0) {  // a flag
      if (value == "true") {
        options.push_back("--" + name);
      } else if (value != "false") {
        throw seqtopo::InputError(where, name + ": a flag takes true or false, got '" + value + "'");
      }
      continue;
    }
    if (value.empty()) throw seqtopo::InputError(where, name + ": no value");
    if (const CLI::Validator* number = find_number_check(*option)) {
      // a list option ("sizes: 1000,3000") checks each element, as CLI11 does on the command line
      const char delimiter = option->get_delimiter();
      std::stringstream items(value);
      for (std::string item; std::getline(items, item, delimiter != '\0' ? delimiter : '\n');) {
        if (const std::string error = (*number)(item); !error.empty()) {
          throw seqtopo::InputError(where, "--" + name + ": " + error);
        }
      }
    }
    options.push_back("--" + name);
    options.push_back(value);
  }
  return options;
}

// `--config FILE` becomes the options it lists, placed right after the subcommand so that the command
// line's own options win (every option takes its last value). FILE holds `name: value` lines; `#` starts
// a comment; `name: true` is a flag.
std::vector<std::string> expand_config(CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> out;
  std::vector<std::string> paths;
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (k > 0 && args[k] == "--config" && k + 1 < args.size()) {
      paths.push_back(args[++k]);
    } else if (k > 0 && args[k].rfind("--config=", 0) == 0) {
      paths.push_back(args[k].substr(9));
    } else {
      out.push_back(args[k]);
    }
  }
  if (paths.empty()) return out;
  const auto [command, at] = target_command(app, out);
  std::vector<std::string> from_files;
  for (const auto& path : paths) {
    const auto options = read_config(path, *command);
    from_files.insert(from_files.end(), options.begin(), options.end());
  }
  out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), from_files.begin(), from_files.end());
  return out;
}

// SIGINT, SIGTERM and SIGHUP stop a run cleanly: the handler only writes the signal's number to a pipe; a thread
// waiting on the pipe removes this process's staging folders and temporary files (after a folder swap in
// progress has finished) and ends the process with 128 + the signal (130, 143, 129) -- unless the run's output
// folder has already been swapped in: then the run goes on to its own end and status. A signal that was ignored
// when seqtopo started (nohup, a background job of a script) stays ignored.
std::atomic<bool> stopping{false};
int signal_pipe[2] = {-1, -1};

extern "C" void on_stop_signal(int signal) {
  const int saved = errno;
  const auto byte = static_cast<unsigned char>(signal);
  [[maybe_unused]] const auto n = ::write(signal_pipe[1], &byte, 1);
  errno = saved;
}

void watch_stop_signals() {
  for (;;) {
    unsigned char byte = 0;
    while (::read(signal_pipe[0], &byte, 1) != 1) {
      if (errno != EINTR) return;
    }
    // Once the new output set is in place the run has done its work: a stop then would only make a caller that
    // checks the status believe the old set is still there. The run ends as it would have.
    if (!seqtopo::io::begin_stop()) continue;
    stopping = true;
    // A second signal while cleaning up ends the process at once (the next run removes what is left).
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_DFL);
    seqtopo::io::remove_staged_outputs_and_exit(128 + byte);
  }
}

void install_stop_signals() {
  if (::pipe2(signal_pipe, O_CLOEXEC) != 0) return;  // no clean stop, the default ones
  bool any = false;
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(s, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction act {};
    act.sa_handler = on_stop_signal;
    sigemptyset(&act.sa_mask);
    act.sa_flags = SA_RESTART;
    any = ::sigaction(s, &act, nullptr) == 0 || any;
  }
  if (any) std::thread(watch_stop_signals).detach();
}

// The exit status, unless a stop signal is being handled: then the watching thread ends the process (with
// 128 + signal) and this one waits for it, printing nothing.
int finish(int status) {
  while (stopping) ::pause();
  return status;
}

}  // namespace

}  // namespace seqtopo::cli

int main(int argc, char** argv) {
  seqtopo::cli::install_stop_signals();
  seqtopo::cli::record_command_line(argc, argv);
  // One line on stderr and the exit status (1: bad input or a failure, 2: a bad command line).
  const auto fail = [](const std::string& message, int status) {
    status = seqtopo::cli::finish(status);
    std::cerr << "seqtopo: error: " << message << "\n";
    return status;
  };
  // Named, so that --help says "Usage: seqtopo [OPTIONS] SUBCOMMAND" (and "seqtopo map [OPTIONS] ...").
  CLI::App app{"seqtopo: topological mapping and localization of a mobile robot with sequence alignment", "seqtopo"};
  app.require_subcommand(1);
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.set_version_flag("--version", "seqtopo " + std::string(seqtopo::version()));
  auto commands = seqtopo::cli::command_registry();
  std::sort(commands.begin(), commands.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& command : commands) command.setup(*app.add_subcommand(command.name, command.description));
  seqtopo::cli::check_all_numeric_options(app);

  try {
    std::vector<std::string> args(argv, argv + argc);
    // An unknown command is said as such (CLI11 would say "A subcommand is required").
    const auto known = [&](const std::string& name) {
      return std::any_of(commands.begin(), commands.end(), [&](const auto& c) { return c.name == name; });
    };
    if (args.size() > 1 && !args[1].empty() && args[1][0] != '-' && !known(args[1])) {
      std::string names;
      for (const auto& command : commands) names += (names.empty() ? "" : ", ") + command.name;
      return fail("unknown command '" + args[1] + "' (commands: " + names + "; see seqtopo --help)", 2);
    }
    args = seqtopo::cli::expand_config(app, args);
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
    return fail(std::string(e.what()) + " (see " + help + " --help)", 2);
  } catch (const seqtopo::InputError& e) {
    return fail(e.subject() + ": " + e.what(), 1);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (the memory estimate did not foresee this run's need)", 1);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
  return seqtopo::cli::finish(0);
}
