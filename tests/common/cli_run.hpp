#pragma once
// Running the seqtopo command line from a test (SEQTOPO_CLI is the binary's path, set by CMake).
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace seqtopo::test_support {

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// `seqtopo ARGS` with stdout discarded, stderr in `stderr_file` (and in *err if given), no terminal
// input; returns the exit status (-1 if it did not exit).
inline int run_cli(const std::string& args, const std::filesystem::path& stderr_file, std::string* err = nullptr) {
  const int raw = std::system(
      (std::string(SEQTOPO_CLI) + " " + args + " >/dev/null 2>" + stderr_file.string() + " </dev/null").c_str());
  if (err) *err = read_file(stderr_file);
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

}  // namespace seqtopo::test_support
