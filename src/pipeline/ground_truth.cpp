#include "seqtopo/pipeline/ground_truth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/lower_case.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/formats/places_csv.hpp"
#include "seqtopo/formats/pose_files.hpp"
#include "seqtopo/formats/vpr_bench_npy.hpp"
#include "seqtopo/image/grey_matrix_file.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

namespace {

// The step between the file's rows of two kept images: 1 when the file lists the images kept, `every` when it
// lists every frame of the recording they were kept from. Anything else is refused, naming the file.
std::size_t row_step(const std::string& file, std::size_t rows, std::size_t images, std::size_t every,
                     const std::string& what) {
  if (rows == images) return 1;
  if (every > 1 && images > 0 && every_kth_count(rows, every) == images) return every;
  std::string fix;
  if (every > 1 && images > 0) {
    fix = fmt::format(
        " (a ground truth lists the {} images kept, or the {} to {} frames of the recording "
        "--every {} kept them from)",
        images, (images - 1) * every + 1, images * every, every);
  }
  throw InputError(file, fmt::format("{}, the sequence has {} images{}", what, images, fix));
}

template <class T>
std::vector<T> thinned(std::vector<T> all, std::size_t step) {
  if (step == 1) return all;
  return every_kth(all, step);
}

// Through the bounded reader: /dev/zero or a FIFO as the ground truth is refused, not read forever.
std::string read_bytes(const fs::path& path) { return read_text_file(path, "ground-truth file"); }

// A CSV's first line with content decides: `query,map` or two fields is a pairs list, anything else poses.
bool csv_is_pairs(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  while (!text.empty()) {
    const auto end = text.find('\n');
    std::string line(text.substr(0, end));
    text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
    line.erase(std::remove_if(line.begin(), line.end(), [](unsigned char c) { return std::isspace(c); }), line.end());
    if (line.empty() || line[0] == '#') continue;
    return line.rfind("query", 0) == 0 || std::count(line.begin(), line.end(), ',') == 1;
  }
  return false;
}

std::vector<Pose2> poses_of(const formats::PoseFile& file) {
  if (!file.timestamped()) return file.per_frame;
  std::vector<Pose2> poses;  // one pose per image, in order (the times are not matched to images here)
  poses.reserve(file.timed.size());
  for (const auto& t : file.timed) poses.push_back(t.pose);
  return poses;
}

std::string keyword_list(std::span<const std::string_view> keywords) {
  std::string list;
  for (auto k : keywords) list += (list.empty() ? "" : ", ") + std::string(k);
  return list;
}

std::string fmt_shape(const DenseMatrix<std::uint8_t>& m) { return fmt::format("is {} x {}", m.rows, m.cols); }

// The largest row and column index listed.
std::pair<std::size_t, std::size_t> largest(const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::size_t a = 0, b = 0;
  for (const auto& [i, j] : pairs) {
    a = std::max(a, i);
    b = std::max(b, j);
  }
  return {a, b};
}

}  // namespace

std::string_view ground_truth_format_name(GroundTruthFormat format) {
  switch (format) {
    case GroundTruthFormat::same_index:
      return "same-index";
    case GroundTruthFormat::matrix:
      return "same-place matrix";
    case GroundTruthFormat::pairs:
      return "pairs CSV";
    case GroundTruthFormat::vpr_bench:
      return "VPR-Bench .npy";
    case GroundTruthFormat::poses:
      return "poses";
  }
  return "?";
}

bool is_same_place_matrix_file(const fs::path& file) {
  const std::string ext = lower_case(file.extension().string());
  if (ext == ".npy") {
    try {
      io::read_npy_header(file);
      return true;
    } catch (const std::exception&) {
      return false;  // not a numeric matrix (objects), or unreadable: the reader says which
    }
  }
  return ext != ".csv" && ext != ".txt" && ext != ".tum" && ext != ".kitti" && !ext.empty();
}

GroundTruthFile read_ground_truth(const std::string& spec, std::span<const std::string_view> keywords,
                                  std::optional<double> radius, std::string_view option) {
  GroundTruthFile t;
  t.name = spec;
  if (std::find(keywords.begin(), keywords.end(), spec) != keywords.end()) {
    t.format = GroundTruthFormat::same_index;
    return t;
  }
  const fs::path path(spec);
  if (!fs::exists(path)) {
    // A word without a folder or an extension was meant as a keyword (a typo of one), not as a file.
    if (spec.find('/') == std::string::npos && !path.has_extension()) {
      if (keywords.empty()) {
        throw InputError(std::string(option), fmt::format("unknown ground-truth keyword '{}': give a file (an N x N "
                                                          "image or .npy, a pairs CSV, VPR-Bench .npy, poses)",
                                                          spec));
      }
      throw InputError(std::string(option), fmt::format("unknown ground-truth keyword '{}', expected one of {} (or "
                                                        "a file)",
                                                        spec, keyword_list(keywords)));
    }
    throw InputError(spec, "no such file");
  }
  if (fs::is_directory(path)) throw InputError(spec, "is a folder, not a ground-truth file");
  const std::string ext = lower_case(path.extension().string());
  if (ext == ".npy") {
    const std::string bytes = read_bytes(path);
    if (formats::npy_holds_objects(bytes)) {
      t.format = GroundTruthFormat::vpr_bench;
      std::vector<formats::QueryMatches> rows;
      try {
        rows = formats::parse_vpr_bench_npy(bytes);
      } catch (const std::invalid_argument& e) {
        throw InputError(spec, std::string("VPR-Bench ground truth: ") + e.what());
      }
      t.listed_rows = rows.size();
      for (const auto& r : rows) {
        for (auto m : r.maps) t.pairs.emplace_back(r.query, m);
      }
    } else {
      t.format = GroundTruthFormat::matrix;
      const auto values = io::read_npy_matrix<float>(path);
      auto m = std::make_shared<DenseMatrix<std::uint8_t>>(values.rows, values.cols);
      for (std::size_t i = 0; i < values.rows; ++i) {
        for (std::size_t j = 0; j < values.cols; ++j) (*m)(i, j) = values(i, j) != 0 ? 1 : 0;
      }
      t.matrix = std::move(m);
    }
  } else if (ext == ".csv" && csv_is_pairs(read_bytes(path))) {
    t.format = GroundTruthFormat::pairs;
    std::string text = read_bytes(path);
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
    try {
      t.pairs = evaluation::parse_pairs_csv(text);
    } catch (const std::invalid_argument& e) {
      throw InputError(spec, e.what());
    }
  } else if (ext == ".csv") {
    t.format = GroundTruthFormat::poses;
    t.poses = formats::read_poses_csv(path);
  } else if (ext == ".txt" || ext == ".tum" || ext == ".kitti" || ext.empty()) {
    t.format = GroundTruthFormat::poses;
    t.poses = poses_of(formats::read_pose_file(path));
  } else {
    t.format = GroundTruthFormat::matrix;
    t.matrix = std::make_shared<DenseMatrix<std::uint8_t>>(image::read_grey_matrix_image(path));
  }
  if (t.format == GroundTruthFormat::poses && (!radius || !(*radius > 0))) {
    throw InputError("--gt-radius", fmt::format("needed (> 0) with a poses ground truth ({}): images within the "
                                                "radius [m] of each other are the same place",
                                                spec));
  }
  return t;
}

void check_same_place_size(const GroundTruthFile& t, std::size_t images, std::size_t every) {
  switch (t.format) {
    case GroundTruthFormat::same_index:
      throw InputError(t.name, "same-index is localize's ground truth; map takes a file");
    case GroundTruthFormat::matrix:
      row_step(t.name, t.matrix->rows == t.matrix->cols ? t.matrix->rows : 0, images, every, fmt_shape(*t.matrix));
      return;
    case GroundTruthFormat::poses:
      row_step(t.name, t.poses.size(), images, every, fmt::format("has {} poses", t.poses.size()));
      return;
    case GroundTruthFormat::pairs:
    case GroundTruthFormat::vpr_bench: {
      if (t.format == GroundTruthFormat::vpr_bench && t.listed_rows > images) {
        throw InputError(t.name, fmt::format("has {} rows, the sequence has {} images", t.listed_rows, images));
      }
      if (t.pairs.empty()) return;
      const auto [a, b] = largest(t.pairs);
      if (std::max(a, b) >= images) {
        throw InputError(t.name, fmt::format("lists image {}, the sequence has {} images (0 to {}; pairs and "
                                             "VPR-Bench rows name the images kept)",
                                             std::max(a, b), images, images == 0 ? 0 : images - 1));
      }
      return;
    }
  }
}

SamePlaceTruth same_place_truth(const GroundTruthFile& t, std::optional<double> radius, std::size_t images,
                                std::size_t every) {
  check_same_place_size(t, images, every);
  switch (t.format) {
    case GroundTruthFormat::matrix: {
      const std::size_t step = t.matrix->rows == images ? 1 : every;
      auto m = t.matrix;
      return {[m, step](std::size_t i, std::size_t j) {
                return (*m)(i * step, j * step) != 0 || (*m)(j * step, i * step) != 0;
              },
              {}};
    }
    case GroundTruthFormat::poses: {
      const std::size_t step = t.poses.size() == images ? 1 : every;
      auto shared = std::make_shared<const std::vector<Pose2>>(thinned(t.poses, step));
      const double r = *radius, r2 = r * r;
      return {[shared, r2](std::size_t i, std::size_t j) {
                const auto& p = *shared;
                const double dx = p[i].x - p[j].x, dy = p[i].y - p[j].y;
                return dx * dx + dy * dy <= r2;
              },
              [shared, r](std::size_t min_separation) {
                return evaluation::images_with_earlier_partner(*shared, r, min_separation);
              }};
    }
    case GroundTruthFormat::pairs:
    case GroundTruthFormat::vpr_bench: {
      // The pairs listed, either way round; the images with an earlier partner come from the list itself.
      auto set = std::make_shared<std::unordered_set<std::uint64_t>>();
      auto list = std::make_shared<std::vector<std::pair<std::size_t, std::size_t>>>();
      for (const auto& [i, j] : t.pairs) {
        if (i == j) continue;
        set->insert(static_cast<std::uint64_t>(i) * images + j);
        set->insert(static_cast<std::uint64_t>(j) * images + i);
        list->emplace_back(std::max(i, j), std::min(i, j));
      }
      return {[set, images](std::size_t i, std::size_t j) {
                return set->count(static_cast<std::uint64_t>(i) * images + j) != 0;
              },
              [list, images](std::size_t min_separation) {
                std::vector<bool> has(images, false);
                for (const auto& [later, earlier] : *list) {
                  if (later - earlier >= min_separation) has[later] = true;
                }
                return has;
              }};
    }
    case GroundTruthFormat::same_index:
      break;
  }
  return {};
}

SamePlaceTruth load_same_place(const fs::path& file, std::optional<double> radius, std::size_t images,
                               std::size_t every) {
  return same_place_truth(read_ground_truth(file.string(), {}, radius), radius, images, every);
}

TruePlaces load_true_places(const fs::path& places_csv, std::size_t images, std::size_t every) {
  TruePlaces t;
  auto all = formats::read_places_csv(places_csv);
  const std::size_t step =
      row_step(places_csv.string(), all.size(), images, every, fmt::format("has {} rows", all.size()));
  t.places = thinned(std::move(all), step);
  const fs::path junctions_file = places_csv.parent_path() / "junctions.csv";
  if (fs::exists(junctions_file)) t.junctions = formats::read_junctions_csv(junctions_file);
  return t;
}

std::vector<Pose2> load_true_poses(const fs::path& poses_csv, std::size_t images, std::size_t every) {
  auto all = formats::read_poses_csv(poses_csv);
  const std::size_t step =
      row_step(poses_csv.string(), all.size(), images, every, fmt::format("has {} poses", all.size()));
  return thinned(std::move(all), step);
}

evaluation::LocalizationTruth localization_truth(const GroundTruthFile& t, std::size_t queries, std::size_t maps,
                                                 const GroundTruthFile* map_poses, std::optional<double> radius) {
  try {
    switch (t.format) {
      case GroundTruthFormat::same_index:
        return evaluation::LocalizationTruth::same_index(queries, maps);
      case GroundTruthFormat::pairs:
        return evaluation::LocalizationTruth::from_pairs(t.pairs, queries, maps);
      case GroundTruthFormat::vpr_bench:
        if (t.listed_rows > queries) {
          throw InputError(t.name, fmt::format("has {} rows, there are {} query frames", t.listed_rows, queries));
        }
        return evaluation::LocalizationTruth::from_pairs(t.pairs, queries, maps);
      case GroundTruthFormat::matrix: {
        const auto& m = *t.matrix;
        if (m.rows != queries || m.cols != maps) {
          throw InputError(t.name,
                           fmt::format("{}, expected {} query rows x {} map columns", fmt_shape(m), queries, maps));
        }
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        for (std::size_t q = 0; q < m.rows; ++q) {
          for (std::size_t j = 0; j < m.cols; ++j) {
            if (m(q, j) != 0) pairs.emplace_back(q, j);
          }
        }
        return evaluation::LocalizationTruth::from_pairs(pairs, queries, maps);
      }
      case GroundTruthFormat::poses: {
        if (!map_poses || map_poses->format != GroundTruthFormat::poses) {
          throw InputError("--gt-map-poses", fmt::format("needed with a poses ground truth ({}): the map frames' "
                                                         "poses",
                                                         t.name));
        }
        if (t.poses.size() != queries) {
          throw InputError(t.name, fmt::format("has {} poses, there are {} query frames", t.poses.size(), queries));
        }
        if (map_poses->poses.size() != maps) {
          throw InputError(map_poses->name,
                           fmt::format("has {} poses, there are {} map frames", map_poses->poses.size(), maps));
        }
        const double r2 = *radius * *radius;
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        for (std::size_t q = 0; q < queries; ++q) {
          for (std::size_t j = 0; j < maps; ++j) {
            const double dx = t.poses[q].x - map_poses->poses[j].x, dy = t.poses[q].y - map_poses->poses[j].y;
            if (dx * dx + dy * dy <= r2) pairs.emplace_back(q, j);
          }
        }
        return evaluation::LocalizationTruth::from_pairs(pairs, queries, maps);
      }
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(t.name, e.what());
  }
  return {};
}

std::size_t default_localization_tolerance(const GroundTruthFile& truth) {
  return truth.format == GroundTruthFormat::same_index ? 2 : 0;
}

}  // namespace seqtopo::pipeline
