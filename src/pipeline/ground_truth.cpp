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

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

SamePlaceTruth load_same_place(const fs::path& file, std::optional<double> radius, std::size_t images) {
  if (file.extension() == ".csv") {
    if (!radius || !(*radius > 0)) throw InputError("--gt-radius", "needed (> 0) with a poses.csv ground truth");
    auto shared = std::make_shared<const std::vector<Pose2>>(formats::read_poses_csv(file));
    if (shared->size() != images) {
      throw InputError(file.string(), fmt::format("has {} poses, the sequence has {} images", shared->size(), images));
    }
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
  if (m->rows != images || m->cols != images) {
    throw InputError(file.string(), fmt::format("is {} x {}, the sequence has {} images", m->rows, m->cols, images));
  }
  return {[m](std::size_t i, std::size_t j) { return (*m)(i, j) != 0 || (*m)(j, i) != 0; }, {}};
}

TruePlaces load_true_places(const fs::path& places_csv, std::size_t images) {
  TruePlaces t;
  t.places = formats::read_places_csv(places_csv);
  if (t.places.size() != images) {
    throw InputError(places_csv.string(),
                     fmt::format("has {} rows, the sequence has {} images", t.places.size(), images));
  }
  const fs::path junctions_file = places_csv.parent_path() / "junctions.csv";
  if (fs::exists(junctions_file)) t.junctions = formats::read_junctions_csv(junctions_file);
  return t;
}

std::vector<Pose2> load_true_poses(const fs::path& poses_csv, std::size_t images) {
  auto truth = formats::read_poses_csv(poses_csv);
  if (truth.size() != images) {
    throw InputError(poses_csv.string(), fmt::format("has {} poses, the sequence has {} images", truth.size(), images));
  }
  return truth;
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
