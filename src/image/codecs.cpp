#include "seqtopo/image/codecs.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

#include "plugin/codec_table.hpp"
#include "png_jpeg.hpp"
#include "seqtopo/core/lower_case.hpp"

namespace seqtopo::image::codecs {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPlugin = "libseqtopo_codecs.so";

// The folder of the program or shared library this code was linked into (the Python extension, for one).
fs::path own_folder() {
  static const int anchor = 0;
  Dl_info info{};
  if (dladdr(&anchor, &info) == 0 || info.dli_fname == nullptr || info.dli_fname[0] != '/') return {};
  return fs::path(info.dli_fname).parent_path();
}

fs::path program_folder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path{} : exe.parent_path();
}

struct Plugin {
  const CodecTable* table = nullptr;
  std::string error;  // why it could not be loaded
};

// dlopen's handle stays open for the life of the process: the table points into the plugin.
const CodecTable* open_table(const std::string& file, std::string& why) {
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* e = dlerror();
    why = e != nullptr ? e : file + ": cannot be opened";
    return nullptr;
  }
  void* symbol = dlsym(handle, "seqtopo_codec_table");
  if (symbol == nullptr) {
    why = file + ": no seqtopo_codec_table (not seqtopo's codecs plugin)";
    return nullptr;
  }
  const CodecTable* (*get)() = nullptr;
  std::memcpy(&get, &symbol, sizeof get);
  const CodecTable* table = get();
  if (table == nullptr || table->version != kCodecTableVersion) {
    why = file + ": a plugin of another seqtopo version";
    return nullptr;
  }
  return table;
}

Plugin load() {
  Plugin p;
  std::vector<std::string> candidates;
  if (const char* chosen = std::getenv("SEQTOPO_CODECS"); chosen != nullptr && chosen[0] != '\0') {
    candidates.emplace_back(chosen);
  } else {
    for (const fs::path& folder : {own_folder(), program_folder()}) {
      if (folder.empty()) continue;
      candidates.push_back((folder / kPlugin).string());
#ifdef SEQTOPO_CODECS_FROM_LIBEXEC
      // seqtopo-main installed in PREFIX/libexec/seqtopo/, the plugin in PREFIX/lib/, wherever PREFIX now is
      candidates.push_back((folder / SEQTOPO_CODECS_FROM_LIBEXEC).lexically_normal().string());
#endif
    }
#ifdef SEQTOPO_CODECS_BUILD_PATH
    candidates.emplace_back(SEQTOPO_CODECS_BUILD_PATH);
#endif
#ifdef SEQTOPO_CODECS_INSTALL_PATH
    candidates.emplace_back(SEQTOPO_CODECS_INSTALL_PATH);
#endif
    candidates.emplace_back(kPlugin);  // the dynamic loader's own search path
  }
  std::string tried, first_failure;
  for (const auto& file : candidates) {
    tried += (tried.empty() ? "" : ", ") + file;
    // A path that names no file is skipped quietly; one that exists but fails to load is the error to report.
    std::error_code ec;
    if (file.find('/') != std::string::npos && !fs::exists(file, ec)) continue;
    std::string why;
    if ((p.table = open_table(file, why)) != nullptr) return p;
    if (first_failure.empty()) first_failure = why;
  }
  p.error = "image codecs: cannot load " + std::string(kPlugin) +
            (first_failure.empty() ? " (looked for " + tried + ")" : ": " + first_failure) +
            "; set SEQTOPO_CODECS to its path";
  return p;
}

const CodecTable& table() {
  static const Plugin plugin = load();
  if (plugin.table == nullptr) throw std::runtime_error(plugin.error);
  return *plugin.table;
}

}  // namespace

void load() { (void)table(); }

bool read_without_plugin(const fs::path& file) {
  const std::string ext = lower_case(file.extension().string());
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

cv::Mat decode(std::span<const std::uint8_t> bytes) {
  cv::Mat out;
  if (direct::decode(bytes, direct::Mode::unchanged, out) != direct::Outcome::unhandled) return out;
  if (!table().decode(bytes.data(), bytes.size(), &out)) out.release();
  return out;
}

cv::Mat read_grey(const fs::path& path) {
  cv::Mat out;
  std::ifstream in(path, std::ios::binary);
  if (in) {
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.bad() && direct::decode(bytes, direct::Mode::grey, out) == direct::Outcome::decoded) return out;
  }
  if (!table().read_grey(path.c_str(), &out)) out.release();
  return out;
}

std::vector<std::uint8_t> encode_png(const cv::Mat& image) { return direct::encode_png(image); }

std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality) {
  return direct::encode_jpeg(image, std::clamp(quality, 1, 100));
}

Video::Video(const fs::path& path) : handle_(table().video_open(path.c_str())) {}

Video::~Video() {
  if (handle_ != nullptr) table().video_close(handle_);
}

Video::Video(Video&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}

double Video::frame_count() const {
  return handle_ != nullptr ? table().video_property(handle_, VideoProperty::frame_count) : 0.0;
}

namespace {
int whole_pixels(double value) { return value >= 1 && value < 1e6 ? static_cast<int>(value) : 0; }
}  // namespace

int Video::frame_width() const {
  return handle_ != nullptr ? whole_pixels(table().video_property(handle_, VideoProperty::frame_width)) : 0;
}

int Video::frame_height() const {
  return handle_ != nullptr ? whole_pixels(table().video_property(handle_, VideoProperty::frame_height)) : 0;
}

bool Video::grab() { return handle_ != nullptr && table().video_grab(handle_); }

bool Video::retrieve(cv::Mat& frame) { return handle_ != nullptr && table().video_retrieve(handle_, &frame); }

}  // namespace seqtopo::image::codecs
