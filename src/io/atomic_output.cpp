#include "seqtopo/io/atomic_output.hpp"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <system_error>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo::io {
namespace fs = std::filesystem;

namespace {
std::string unique_suffix() {
  static int counter = 0;
  return ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}
}  // namespace

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  const fs::path tmp = path.string() + unique_suffix();
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path.string(), "cannot open for writing");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path.string(), "write failed");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path.string(), "cannot move into place: " + ec.message());
  }
}

OutputDirectory::OutputDirectory(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) throw InputError(dir_.string(), "cannot create output directory");
  staging_ = dir_ / (".staging" + unique_suffix());
  fs::create_directory(staging_, ec);
  if (ec) throw InputError(dir_.string(), "cannot write in output directory: " + ec.message());
}

OutputDirectory::~OutputDirectory() {
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

fs::path OutputDirectory::staged(const std::string& name) {
  if (std::find(names_.begin(), names_.end(), name) == names_.end()) names_.push_back(name);
  const fs::path path = staging_ / name;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  return path;
}

void OutputDirectory::write(const std::string& name, std::string_view bytes) {
  const fs::path path = staged(name);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw InputError((dir_ / name).string(), "write failed");
}

std::vector<fs::path> OutputDirectory::commit() {
  std::vector<fs::path> written;
  for (const auto& name : names_) {
    const fs::path from = staging_ / name;
    if (!fs::exists(from)) throw InputError((dir_ / name).string(), "was never written");
  }
  for (const auto& name : names_) {
    std::error_code ec;
    const fs::path to = dir_ / name;
    fs::create_directories(to.parent_path(), ec);
    // A staged folder (e.g. images/) replaces the old one whole.
    if (fs::is_directory(staging_ / name) && fs::is_directory(to)) fs::remove_all(to, ec);
    fs::rename(staging_ / name, to, ec);
    if (ec) throw InputError((dir_ / name).string(), "cannot move into place: " + ec.message());
    written.push_back(dir_ / name);
  }
  committed_ = true;
  return written;
}

}  // namespace seqtopo::io
