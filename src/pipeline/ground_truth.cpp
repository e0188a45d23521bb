#include "seqtopo/pipeline/ground_truth.hpp"

#include <fmt/format.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/formats/places_csv.hpp"
#include "seqtopo/image/grey_matrix_file.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

namespace {

// The step between the file's rows of two kept images: 1 when the file lists the images kept, `every` when it
// lists every frame of the recording they were kept from. Anything else is refused, naming the file.
std::size_t row_step(const fs::path& file, std::size_t rows, std::size_t images, std::size_t every,
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
  throw InputError(file.string(), fmt::format("{}, the sequence has {} images{}", what, images, fix));
}

template <class T>
std::vector<T> thinned(std::vector<T> all, std::size_t step) {
  if (step == 1) return all;
  return every_kth(all, step);
}

}  // namespace

SamePlaceTruth load_same_place(const fs::path& file, std::optional<double> radius, std::size_t images,
                               std::size_t every) {
  if (file.extension() == ".csv") {
    if (!radius || !(*radius > 0)) throw InputError("--gt-radius", "needed (> 0) with a poses.csv ground truth");
    auto all = formats::read_poses_csv(file);
    const std::size_t step = row_step(file, all.size(), images, every, fmt::format("has {} poses", all.size()));
    auto shared = std::make_shared<const std::vector<Pose2>>(thinned(std::move(all), step));
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
  auto m = std::make_shared<DenseMatrix<std::uint8_t>>(image::read_grey_matrix_image(file));
  const std::string size = fmt::format("is {} x {}", m->rows, m->cols);
  const std::size_t step = row_step(file, m->rows == m->cols ? m->rows : 0, images, every, size);
  return {[m, step](std::size_t i, std::size_t j) {
            return (*m)(i * step, j * step) != 0 || (*m)(j * step, i * step) != 0;
          },
          {}};
}

TruePlaces load_true_places(const fs::path& places_csv, std::size_t images, std::size_t every) {
  TruePlaces t;
  auto all = formats::read_places_csv(places_csv);
  const std::size_t step = row_step(places_csv, all.size(), images, every, fmt::format("has {} rows", all.size()));
  t.places = thinned(std::move(all), step);
  const fs::path junctions_file = places_csv.parent_path() / "junctions.csv";
  if (fs::exists(junctions_file)) t.junctions = formats::read_junctions_csv(junctions_file);
  return t;
}

std::vector<Pose2> load_true_poses(const fs::path& poses_csv, std::size_t images, std::size_t every) {
  auto all = formats::read_poses_csv(poses_csv);
  const std::size_t step = row_step(poses_csv, all.size(), images, every, fmt::format("has {} poses", all.size()));
  return thinned(std::move(all), step);
}

LocalizationTruthSource read_localization_truth(const std::string& gt) {
  LocalizationTruthSource s;
  if (gt == "same-index") {
    s.same_index = true;
    return s;
  }
  s.file = gt;
  std::ifstream in(gt, std::ios::binary);
  if (!in) throw InputError(gt, "cannot open the ground-truth file");
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    s.pairs = evaluation::parse_pairs_csv(ss.str());
  } catch (const std::invalid_argument& e) {
    throw InputError(gt, e.what());
  }
  return s;
}

evaluation::LocalizationTruth localization_truth(const LocalizationTruthSource& source, std::size_t queries,
                                                 std::size_t maps) {
  try {
    return source.same_index ? evaluation::LocalizationTruth::same_index(queries, maps)
                             : evaluation::LocalizationTruth::from_pairs(source.pairs, queries, maps);
  } catch (const std::invalid_argument& e) {
    throw InputError(source.same_index ? std::string("same-index") : source.file.string(), e.what());
  }
}

}  // namespace seqtopo::pipeline
