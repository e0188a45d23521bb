#pragma once
// Ground truth read from the files users bring (INTERFACE.md, "Ground truth formats"). Each reader checks
// the size against the sequence and throws InputError naming the file. With `every` > 1 (--every K kept frames
// 0, K, 2K, ... of the recording), a file may list the frames kept or every frame of the recording, as an
// odometry file does: one of N rows with (N + K - 1) / K equal to the images kept is thinned alike.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"

namespace seqtopo::pipeline {

// Same place: an N x N image (non-zero at (i, j) or (j, i)), or poses.csv (index,x,y[,theta]) and a radius
// [m]: within `radius` of each other. A poses.csv without a radius is refused (subject --gt-radius). From poses
// the images with an earlier partner are also found from the positions (evaluation::EarlierPartners); an image's
// relation is tested pair by pair.
struct SamePlaceTruth {
  evaluation::SamePlace same_place;
  evaluation::EarlierPartners earlier_partners;  // empty for an image
};
SamePlaceTruth load_same_place(const std::filesystem::path& file, std::optional<double> radius, std::size_t images,
                               std::size_t every = 1);

// The true place of every image (places.csv, index,place) and the true junction places (junctions.csv in the
// same folder, when there is one).
struct TruePlaces {
  std::vector<int> places;
  std::vector<int> junctions;
};
TruePlaces load_true_places(const std::filesystem::path& places_csv, std::size_t images, std::size_t every = 1);

// True poses (poses.csv), one per image.
std::vector<Pose2> load_true_poses(const std::filesystem::path& poses_csv, std::size_t images, std::size_t every = 1);

// `seqtopo localize --gt`: "same-index" (query k is map k), or a CSV file of query,map pairs. The file is read
// by read_localization_pairs (before the work, so that a bad file fails fast) and sized by localization_truth.
struct LocalizationTruthSource {
  bool same_index = false;
  std::filesystem::path file;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // read from `file`
};
// Throws InputError naming the file when it cannot be read or parsed.
LocalizationTruthSource read_localization_truth(const std::string& gt);
evaluation::LocalizationTruth localization_truth(const LocalizationTruthSource& source, std::size_t queries,
                                                 std::size_t maps);

}  // namespace seqtopo::pipeline
