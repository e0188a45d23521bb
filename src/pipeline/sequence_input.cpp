#include "seqtopo/pipeline/sequence_input.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <system_error>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

InputKind parse_input_kind(std::string_view name) {
  if (name == "auto" || name == "automatic") return InputKind::automatic;
  if (name == "images") return InputKind::images;
  if (name == "video") return InputKind::video;
  if (name == "descriptors") return InputKind::descriptors;
  if (name == "similarity") return InputKind::similarity;
  throw std::invalid_argument("unknown input kind '" + std::string(name) +
                              "' (expected auto, images, video, descriptors or similarity)");
}

std::string_view input_kind_name(InputKind kind) {
  switch (kind) {
    case InputKind::automatic:
      return "auto";
    case InputKind::images:
      return "images";
    case InputKind::video:
      return "video";
    case InputKind::descriptors:
      return "descriptors";
    case InputKind::similarity:
      return "similarity";
  }
  return "?";
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// <0, 0, >0 under the natural order without the final byte-order tie-break.
int natural_compare(std::string_view a, std::string_view b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && is_digit(a[ie])) ++ie;
      while (je < b.size() && is_digit(b[je])) ++je;
      std::size_t iz = i, jz = j;  // skip leading zeros: "007" == "7" by value
      while (iz + 1 < ie && a[iz] == '0') ++iz;
      while (jz + 1 < je && b[jz] == '0') ++jz;
      const std::string_view da = a.substr(iz, ie - iz), db = b.substr(jz, je - jz);
      if (da.size() != db.size()) return da.size() < db.size() ? -1 : 1;
      if (const int c = da.compare(db); c != 0) return c;
      i = ie;
      j = je;
    } else {
      const int ca = std::tolower(static_cast<unsigned char>(a[i]));
      const int cb = std::tolower(static_cast<unsigned char>(b[j]));
      if (ca != cb) return ca < cb ? -1 : 1;
      ++i;
      ++j;
    }
  }
  if (i < a.size()) return 1;
  if (j < b.size()) return -1;
  return 0;
}

bool is_image_extension(const fs::path& p) {
  static const char* const known[] = {".png",  ".jpg", ".jpeg", ".bmp", ".tif", ".tiff",
                                      ".webp", ".pgm", ".ppm",  ".pnm", ".jp2"};
  const std::string ext = lower(p.extension().string());
  return std::any_of(std::begin(known), std::end(known), [&](const char* k) { return ext == k; });
}

}  // namespace

bool natural_less(std::string_view a, std::string_view b) {
  const int c = natural_compare(a, b);
  return c != 0 ? c < 0 : a < b;
}

InputKind resolve_input_kind(const SequenceInput& input) {
  if (input.kind != InputKind::automatic) return input.kind;
  std::error_code ec;
  const auto status = fs::status(input.path, ec);
  if (ec || !fs::exists(status)) throw InputError(input.path.string(), "no such file or directory");
  if (fs::is_directory(status)) return InputKind::images;
  if (lower(input.path.extension().string()) == ".npy") {
    return lower(input.path.filename().string()).find("similarity") != std::string::npos ? InputKind::similarity
                                                                                         : InputKind::descriptors;
  }
  return InputKind::video;
}

std::vector<fs::path> list_images(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "not a folder");
  std::vector<fs::path> files;
  fs::directory_iterator it(folder, ec);
  if (ec) throw InputError(folder.string(), "cannot list folder: " + ec.message());
  for (const auto& entry : it) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.' || lower(name).rfind("ground_truth", 0) == 0) continue;
    if (!is_image_extension(entry.path())) continue;
    if (!entry.is_regular_file(ec)) continue;
    files.push_back(entry.path());
  }
  if (files.empty()) throw InputError(folder.string(), "folder holds no image (png, jpg, bmp, tif, ...)");
  std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
    return natural_less(a.filename().string(), b.filename().string());
  });
  return files;
}

}  // namespace seqtopo::pipeline
