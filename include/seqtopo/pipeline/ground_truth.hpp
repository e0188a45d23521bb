#pragma once
// Ground truth read from the files users bring (INTERFACE.md, "Ground truth formats"), one reader for `map` and
// `localize`: read_ground_truth() recognizes the format and parses the file (before any work, so that a bad file
// costs one line and no time), and same_place_truth() / localization_truth() size it against the sequences,
// throwing InputError naming the file. The formats:
//  * an image (bmp, png, ...) or a numeric .npy matrix: non-zero at row i, column j <=> i and j are the same place;
//  * a pairs CSV `query,map` (header optional): the pairs listed are the same place, and only those;
//  * VPR-Bench's ground_truth_new.npy (formats/vpr_bench_npy.hpp): [query, [map frames]] per row;
//  * poses: `index,x,y[,theta]` CSV, TUM or KITTI (one pose per image, in order) with a radius [m]: the same place
//    within the radius;
//  * the keyword same-index (localize only): query k is map k.
// With `every` > 1 (--every K kept frames 0, K, 2K, ... of the recording), an image, matrix or poses file may list
// the frames kept or every frame of the recording, as an odometry file does: one of N rows with (N + K - 1) / K
// equal to the images kept is thinned alike. Pairs and VPR-Bench lists name the frames kept.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/core/pose2.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"

namespace seqtopo::pipeline {

enum class GroundTruthFormat { same_index, matrix, pairs, vpr_bench, poses };
std::string_view ground_truth_format_name(GroundTruthFormat format);

// A ground truth as read, not yet sized against a sequence.
struct GroundTruthFile {
  GroundTruthFormat format = GroundTruthFormat::matrix;
  std::string name;                                         // the file (or keyword) as given, for messages
  std::shared_ptr<const DenseMatrix<std::uint8_t>> matrix;  // matrix: rows x columns, non-zero = same place
  std::vector<std::pair<std::size_t, std::size_t>> pairs;   // pairs, vpr_bench: (query or row, map or column)
  std::size_t listed_rows = 0;                              // vpr_bench: rows of the file (one per query)
  std::vector<Pose2> poses;                                 // poses: one per image
};

// Reads `spec`: a keyword of `keywords` (localize: same-index), or a file whose format is recognized by its
// extension and content. `radius` is required (> 0) with poses and refused without them. Throws InputError naming
// `option`, the keyword or the file: an unknown keyword ("unknown ground-truth keyword 'X', expected one of ..."),
// a missing or unreadable file, a format error.
GroundTruthFile read_ground_truth(const std::string& spec, std::span<const std::string_view> keywords,
                                  std::optional<double> radius, std::string_view option = "--ground-truth");

// Whether `file` is read as an N x N matrix (an image, or a numeric .npy; VPR-Bench's object arrays are lists), from
// its name and, for a .npy, its header: for checks that must not read N^2 values (streaming refuses them).
bool is_same_place_matrix_file(const std::filesystem::path& file);

// Same place for `seqtopo map`: the relation (symmetric) and, where the format allows it, the images with an
// earlier partner found without testing every pair (evaluation::EarlierPartners).
struct SamePlaceTruth {
  evaluation::SamePlace same_place;
  evaluation::EarlierPartners earlier_partners;  // empty: found from the relation
};
// Throws InputError naming the file when its size does not fit `images` (thinned by `every`, see above).
SamePlaceTruth same_place_truth(const GroundTruthFile& truth, std::optional<double> radius, std::size_t images,
                                std::size_t every = 1);
// Only checks the size (as same_place_truth does), for a check before the work.
void check_same_place_size(const GroundTruthFile& truth, std::size_t images, std::size_t every = 1);
// read_ground_truth (no keyword) then same_place_truth.
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

// `seqtopo localize --ground-truth` (alias --gt): truth[q] = the map frames of query q. A matrix is queries x map
// frames; pairs and VPR-Bench rows are (query, map); poses are the query frames' and need `map_poses` (the map
// frames', --gt-map-poses) and the radius. Throws InputError naming the file when the sizes disagree.
evaluation::LocalizationTruth localization_truth(const GroundTruthFile& truth, std::size_t queries, std::size_t maps,
                                                 const GroundTruthFile* map_poses = nullptr,
                                                 std::optional<double> radius = std::nullopt);

// The tolerance [frames] localize applies when none is given: same-index names one frame per query, so +-2 frames
// around it count; every file lists the true frames themselves, so 0 (an explicit --tolerance still widens them).
std::size_t default_localization_tolerance(const GroundTruthFile& truth);

}  // namespace seqtopo::pipeline
