#pragma once
// Running a command from a test: its exit status, everything it wrote to stdout and stderr, and optional
// text on its stdin.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace seqtopo::test_support {

struct CommandResult {
  int status = -1;  // the exit status; -1 if the command did not exit (killed by a signal)
  std::string out;  // its stdout
  std::string err;  // its stderr
  // The last line of stderr, without its newline ("" when stderr is empty).
  std::string err_last_line() const {
    std::string text = err;
    if (!text.empty() && text.back() == '\n') text.pop_back();
    return text.substr(text.rfind('\n') + 1);  // no newline: npos + 1 == 0, the whole text
  }
};

namespace detail {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// An anonymous temporary file, gone when closed.
inline File temporary_file() {
  File file(std::tmpfile(), &std::fclose);
  if (!file) throw std::runtime_error(std::string("run_command: tmpfile: ") + std::strerror(errno));
  return file;
}

inline std::string read_all(std::FILE* file) {
  std::rewind(file);
  std::string text;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) text.append(buffer.data(), n);
  return text;
}

// posix_spawn_file_actions_t, destroyed on every path out.
struct FileActions {
  posix_spawn_file_actions_t actions{};
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
};

}  // namespace detail

// `sh -c COMMAND` with `input` on its stdin (none: /dev/null, never the terminal); its stdout and stderr
// are captured whole (in temporary files, so a chatty command cannot block on a full pipe). Start a
// simple command with `exec` for a crash to give -1 rather than the shell's 128 + signal number.
inline CommandResult run_command(const std::string& command, const std::optional<std::string>& input = std::nullopt) {
  const detail::File out = detail::temporary_file(), err = detail::temporary_file();
  detail::File in(nullptr, &std::fclose);
  detail::FileActions files;
  if (input) {
    in = detail::temporary_file();
    if (std::fwrite(input->data(), 1, input->size(), in.get()) != input->size() || std::fflush(in.get()) != 0) {
      throw std::runtime_error("run_command: cannot write the input");
    }
    std::rewind(in.get());
    posix_spawn_file_actions_adddup2(&files.actions, fileno(in.get()), STDIN_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&files.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  }
  posix_spawn_file_actions_adddup2(&files.actions, fileno(out.get()), STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&files.actions, fileno(err.get()), STDERR_FILENO);
  std::string sh = "sh", dash_c = "-c", text = command;
  std::array<char*, 4> argv{sh.data(), dash_c.data(), text.data(), nullptr};
  pid_t pid = 0;
  if (const int e = posix_spawn(&pid, "/bin/sh", &files.actions, nullptr, argv.data(), environ); e != 0) {
    throw std::runtime_error("run_command: cannot start /bin/sh: " + std::string(std::strerror(e)));
  }
  int raw = 0;
  while (waitpid(pid, &raw, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("run_command: waitpid: " + std::string(std::strerror(errno)));
  }
  CommandResult result;
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  result.out = detail::read_all(out.get());
  result.err = detail::read_all(err.get());
  return result;
}

}  // namespace seqtopo::test_support
