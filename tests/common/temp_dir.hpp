#pragma once
// A scratch folder for one test, removed with everything in it when the test ends (unless SEQTOPO_KEEP_TEST_FILES is
// set), and reading a file whole.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace seqtopo::test_support {

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() / ("seqtopo-test-" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(path);
  }
  // SEQTOPO_KEEP_TEST_FILES=1 keeps the folder for a look after a failure.
  ~TempDir() {
    if (std::getenv("SEQTOPO_KEEP_TEST_FILES") == nullptr) std::filesystem::remove_all(path);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  void touch(const std::string& name) const { std::ofstream(path / name) << "x"; }
  // Writes `text` to the file `name` in the folder and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

// The bytes of the file at `path` ("" if it cannot be read).
inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace seqtopo::test_support
