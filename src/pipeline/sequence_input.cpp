#include "seqtopo/pipeline/sequence_input.hpp"

#include <string.h>  // strverscmp (glibc)

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <system_error>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/lower_case.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

InputKind parse_input_kind(std::string_view name) {
  if (name == "auto" || name == "automatic") return InputKind::automatic;
  if (name == "images") return InputKind::images;
  if (name == "video") return InputKind::video;
  if (name == "descriptors") return InputKind::descriptors;
  if (name == "similarity") return InputKind::similarity;
  if (name == "bag") return InputKind::bag;
  throw std::invalid_argument("unknown input kind '" + std::string(name) +
                              "' (expected auto, images, video, descriptors, similarity or bag)");
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
    case InputKind::bag:
      return "bag";
  }
  return "?";
}

namespace {

bool is_image_extension(const fs::path& p) {
  static const char* const known[] = {".png",  ".jpg", ".jpeg", ".bmp", ".tif", ".tiff",
                                      ".webp", ".pgm", ".ppm",  ".pnm", ".jp2"};
  const std::string ext = lower_case(p.extension().string());
  return std::any_of(std::begin(known), std::end(known), [&](const char* k) { return ext == k; });
}

}  // namespace

bool natural_less(std::string_view a, std::string_view b) {
  // strverscmp needs NUL-terminated strings; names hold no NUL.
  return ::strverscmp(std::string(a).c_str(), std::string(b).c_str()) < 0;
}

InputKind resolve_input_kind(const SequenceInput& input) {
  if (input.kind != InputKind::automatic) return input.kind;
  std::error_code ec;
  const auto status = fs::status(input.path, ec);
  if (ec || !fs::exists(status)) throw InputError(input.path.string(), "no such file or directory");
  // A device or FIFO would be read forever (/dev/zero) or waited for: refused before any work.
  if (!fs::is_directory(status) && !fs::is_regular_file(status)) {
    throw InputError(input.path.string(), special_file_reason(input.path) + ", not an input file");
  }
  const std::string ext = lower_case(input.path.extension().string());
  if (fs::is_directory(status)) {
    // A ROS 2 bag folder: metadata.yaml beside its .db3 or .mcap storage files.
    if (fs::exists(input.path / "metadata.yaml", ec)) {
      for (const auto& entry : fs::directory_iterator(input.path, ec)) {
        const std::string e = lower_case(entry.path().extension().string());
        if (e == ".db3" || e == ".mcap") return InputKind::bag;
      }
    }
    return InputKind::images;
  }
  if (ext == ".bag" || ext == ".db3" || ext == ".mcap") return InputKind::bag;
  if (ext == ".npy") {
    return lower_case(input.path.filename().string()).find("similarity") != std::string::npos ? InputKind::similarity
                                                                                              : InputKind::descriptors;
  }
  return InputKind::video;
}

namespace {

// Why an entry with an image extension cannot be read as a file, or "" when it is a regular file (the check
// every file named by the user goes through, core/text_file.hpp).
std::string unreadable_reason(const fs::directory_entry& entry) {
  // The type the folder listing gave: a regular file needs no system call to be told one (a folder of 10^4
  // images is 2 x 10^4 stat calls otherwise).
  std::error_code ec;
  if (entry.symlink_status(ec).type() == fs::file_type::regular && !ec) return {};
  return special_file_reason(entry.path());
}

bool hidden_or_truth(const std::string& name) {
  return name.empty() || name[0] == '.' || lower_case(name).rfind("ground_truth", 0) == 0;
}

// Natural order of relative paths, folder name by folder name.
bool path_less(const fs::path& a, const fs::path& b) {
  auto ia = a.begin(), ib = b.begin();
  for (; ia != a.end() && ib != b.end(); ++ia, ++ib) {
    const std::string na = ia->string(), nb = ib->string();
    if (na != nb) return natural_less(na, nb);
  }
  return ia == a.end() && ib != b.end();
}

}  // namespace

ImageListing list_images(const fs::path& folder, const ListOptions& options) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "not a folder");
  ImageListing listing;
  std::vector<fs::path> relative;
  auto consider = [&](const fs::directory_entry& entry) {
    const std::string name = entry.path().filename().string();
    if (hidden_or_truth(name) || !is_image_extension(entry.path())) return;
    if (options.recursive) {
      // A folder named like an image is walked into by the recursive iterator, not listed.
      std::error_code e;
      if (fs::is_directory(entry.symlink_status(e)) && !e) return;
    }
    const std::string why = unreadable_reason(entry);
    if (!why.empty()) {
      if (!options.skip_unreadable) {
        throw InputError(entry.path().string(),
                         "has an image's name but is " + why + " (--skip-unreadable leaves such entries out)");
      }
      listing.skipped.emplace_back(entry.path(), why);
      return;
    }
    relative.push_back(entry.path().lexically_relative(folder));
  };
  if (options.recursive) {
    fs::recursive_directory_iterator it(folder, fs::directory_options::none, ec);
    if (ec) throw InputError(folder.string(), "cannot list folder: " + ec.message());
    for (const fs::recursive_directory_iterator end; it != end; it.increment(ec)) {
      if (ec) throw InputError(folder.string(), "cannot list folder: " + ec.message());
      const std::string name = it->path().filename().string();
      std::error_code e;
      if (it->is_directory(e) && !it->is_symlink(e) && !name.empty() && name[0] == '.') {
        it.disable_recursion_pending();  // hidden folders (.git, ...) are not part of the sequence
        continue;
      }
      consider(*it);
    }
    if (ec) throw InputError(folder.string(), "cannot list folder: " + ec.message());
  } else {
    fs::directory_iterator it(folder, ec);
    if (ec) throw InputError(folder.string(), "cannot list folder: " + ec.message());
    for (const auto& entry : it) consider(entry);
  }
  std::sort(relative.begin(), relative.end(), path_less);
  for (const auto& r : relative) {
    fs::path file = folder / r;
    if (options.skip_unreadable) {
      try {
        (void)image::load_image(file);
      } catch (const InputError& e) {
        listing.skipped.emplace_back(file, e.what());
        continue;
      }
    }
    listing.files.push_back(std::move(file));
  }
  if (listing.files.empty()) {
    throw InputError(folder.string(), options.recursive
                                          ? "folder and its subfolders hold no readable image (png, jpg, bmp, tif, ...)"
                                          : "folder holds no readable image (png, jpg, bmp, tif, ...)");
  }
  return listing;
}

std::vector<fs::path> list_images(const fs::path& folder) { return list_images(folder, ListOptions{}).files; }

ImageListing list_input_images(const SequenceInput& input) {
  if (input.listing) return *input.listing;
  ImageListing listing =
      list_images(input.path, ListOptions{.recursive = input.recursive, .skip_unreadable = input.skip_unreadable});
  if (input.every > 1) listing.files = every_kth(listing.files, input.every);
  return listing;
}

DenseMatrix<float> read_input_rows(const SequenceInput& input) {
  DenseMatrix<float> all = io::read_npy_matrix<float>(input.path);
  if (input.every <= 1 || all.rows == 0) return all;
  DenseMatrix<float> kept(every_kth_count(all.rows, input.every), all.cols);
  for (std::size_t r = 0; r < kept.rows; ++r) {
    const auto row = all.row(r * input.every);
    std::copy(row.begin(), row.end(), kept.row(r).begin());
  }
  return kept;
}

void refuse_every_for_similarity(const SequenceInput& input) {
  if (input.every > 1) {
    throw InputError("--every",
                     "keeps every K-th frame of images, videos, bags and descriptors; the similarity "
                     "matrix " +
                         input.path.string() + " is used whole");
  }
}

std::string image_name(const fs::path& folder, const fs::path& file, bool recursive) {
  return recursive ? file.lexically_relative(folder).generic_string() : file.filename().string();
}

}  // namespace seqtopo::pipeline
