#pragma once
// Outputs appear whole or not at all: every file is written to a temporary name beside its target and
// renamed into place (rename is atomic on POSIX file systems).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::io {

// Writes bytes to path atomically. Throws InputError naming the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Collects the files of one command's output directory and moves them in together at commit(), so a
// failure half-way leaves the directory as it was. Files are first written to a hidden staging folder
// inside the output directory; an uncommitted OutputDirectory removes it.
class OutputDirectory {
 public:
  explicit OutputDirectory(std::filesystem::path dir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  // Where to write `name` before commit (writers may create it directly there).
  std::filesystem::path staged(const std::string& name);
  void write(const std::string& name, std::string_view bytes);
  // Moves every staged file into the directory; returns the final paths.
  std::vector<std::filesystem::path> commit();
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::filesystem::path staging_;
  std::vector<std::string> names_;
  bool committed_ = false;
};

}  // namespace seqtopo::io
