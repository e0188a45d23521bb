// Ground truth files sized against the sequence (ground_truth.hpp): the images kept, or every frame of the
// recording --every thinned, and a clear error naming the file otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "common/input_error_text.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/plot/png.hpp"

namespace seqtopo::pipeline {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

using test_support::error_of;

// A same-place image of `n` frames: frames i and j are one place when i % 3 == j % 3 and (i * j) % 5 != 1,
// a pattern with no symmetry in the step, so a wrong thinning shows.
fs::path same_place_image(const TempDir& dir, int n) {
  RgbImage m(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i % 3 == j % 3 && (i * j) % 5 != 1) std::fill_n(m.at(j, i), 3, std::uint8_t{255});
    }
  }
  const fs::path file = dir.path / ("truth" + std::to_string(n) + ".png");
  plot::write_png(file, m);
  return file;
}

bool same(int i, int j) { return (i % 3 == j % 3 && (i * j) % 5 != 1) || (j % 3 == i % 3 && (j * i) % 5 != 1); }

TEST(GroundTruth, AnImageOfTheRecordingIsThinnedAsEveryThinnedTheFrames) {
  TempDir dir;
  const auto file = same_place_image(dir, 11);  // frames 0..10; --every 3 keeps 0, 3, 6, 9
  const auto kept = load_same_place(file, std::nullopt, 4, 3);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_EQ(kept.same_place(i, j), same(3 * i, 3 * j)) << i << "," << j;
  }
  // The same file as the kept images' own truth when it has their count.
  const auto whole = load_same_place(file, std::nullopt, 11, 3);
  for (int i = 0; i < 11; ++i) {
    for (int j = 0; j < 11; ++j) EXPECT_EQ(whole.same_place(i, j), same(i, j)) << i << "," << j;
  }
}

TEST(GroundTruth, ARecordingOfAnotherLengthIsRefusedWithTheSizesThatFit) {
  TempDir dir;
  const auto file = same_place_image(dir, 11);
  // 11 frames at --every 2 would keep 6: the run kept 4 (a recording of 7 or 8 frames).
  EXPECT_EQ(error_of([&] { load_same_place(file, std::nullopt, 4, 2); }),
            file.string() +
                ": is 11 x 11, the sequence has 4 images (a ground truth lists the 4 images kept, or the 7 to 8 "
                "frames of the recording --every 2 kept them from)");
  // Without --every the recording is the sequence.
  EXPECT_EQ(error_of([&] { load_same_place(file, std::nullopt, 4); }),
            file.string() + ": is 11 x 11, the sequence has 4 images");
}

TEST(GroundTruth, PosesAndPlacesOfTheRecordingAreThinnedToo) {
  TempDir dir;
  std::string poses = "index,x,y,theta\n", places = "index,place\n";
  for (int k = 0; k < 7; ++k) {
    poses += std::to_string(k) + "," + std::to_string(k * k) + ",0,0\n";
    places += std::to_string(k) + "," + std::to_string(10 + k) + "\n";
  }
  const auto poses_file = dir.write("poses.csv", poses);
  const auto places_dir = dir.path / "truth";
  fs::create_directory(places_dir);
  const auto places_file = places_dir / "places.csv";
  { std::ofstream(places_file) << places; }
  const auto kept = load_true_poses(poses_file, 3, 3);  // frames 0, 3, 6
  ASSERT_EQ(kept.size(), 3U);
  EXPECT_EQ(kept[1].x, 9.0);
  EXPECT_EQ(kept[2].x, 36.0);
  EXPECT_EQ(load_true_places(places_file, 3, 3).places, (std::vector<int>{10, 13, 16}));
  EXPECT_EQ(load_true_places(places_file, 7, 3).places.size(), 7U);
  // Within 20 m, at the recording's positions of the kept frames: x 0 and 9 are, 9 and 36 are not.
  const auto radius = load_same_place(poses_file, 20.0, 3, 3);
  EXPECT_TRUE(radius.same_place(0, 1));   // 0 and 9
  EXPECT_FALSE(radius.same_place(1, 2));  // 9 and 36
  EXPECT_EQ(error_of([&] { load_true_poses(poses_file, 2, 3); }),
            poses_file.string() +
                ": has 7 poses, the sequence has 2 images (a ground truth lists the 2 images kept, or the 4 to 6 "
                "frames of the recording --every 3 kept them from)");
}

// A pairs CSV and VPR-Bench's lists: the pairs either way round, and the images with an earlier partner found
// from the list agree with those found by testing every pair of the relation.
TEST(GroundTruth, PairsListsGiveASymmetricRelationAndItsEarlierPartners) {
  TempDir dir;
  const auto file = dir.write("pairs.csv", "\xEF\xBB\xBFquery,map\n5,1\n2,6\n7,7\n9,8\n");
  const auto truth = read_ground_truth(file.string(), {}, std::nullopt);
  EXPECT_EQ(truth.format, GroundTruthFormat::pairs);
  const auto same = same_place_truth(truth, std::nullopt, 10);
  EXPECT_TRUE(same.same_place(5, 1));
  EXPECT_TRUE(same.same_place(1, 5));
  EXPECT_TRUE(same.same_place(6, 2));
  EXPECT_FALSE(same.same_place(5, 2));
  for (std::size_t separation : {0U, 1U, 2U, 4U, 5U}) {
    EXPECT_EQ(same.earlier_partners(separation),
              evaluation::images_with_earlier_partner(10, same.same_place, separation))
        << separation;
  }
  EXPECT_EQ(error_of([&] { same_place_truth(truth, std::nullopt, 8); }),
            file.string() +
                ": lists image 9, the sequence has 8 images (0 to 7; pairs and VPR-Bench rows name the images kept)");
}

TEST(GroundTruth, KeywordsTyposAndFilesAreToldApart) {
  TempDir dir;
  constexpr std::string_view keywords[] = {"same-index"};
  EXPECT_EQ(read_ground_truth("same-index", keywords, std::nullopt).format, GroundTruthFormat::same_index);
  EXPECT_EQ(error_of([&] { read_ground_truth("same_index", keywords, std::nullopt); }),
            "--ground-truth: unknown ground-truth keyword 'same_index', expected one of same-index (or a file)");
  const auto missing = (dir.path / "truth.csv").string();
  EXPECT_EQ(error_of([&] { read_ground_truth(missing, keywords, std::nullopt); }), missing + ": no such file");
  const auto poses = dir.write("poses.txt", "0 1 2 0 0 0 0 1\n");  // TUM
  EXPECT_EQ(error_of([&] { read_ground_truth(poses.string(), {}, std::nullopt); }),
            "--gt-radius: needed (> 0) with a poses ground truth (" + poses.string() +
                "): images within the radius [m] of each other are the same place");
  EXPECT_EQ(read_ground_truth(poses.string(), {}, 1.0).poses.size(), 1U);
}

// localize: a pairs file is taken as listed; an image is queries x map frames.
TEST(GroundTruth, LocalizationTruthFromEachFormat) {
  TempDir dir;
  const auto pairs = read_ground_truth(dir.write("p.csv", "0,3\n2,1\n2,4\n").string(), {}, std::nullopt);
  const auto t = localization_truth(pairs, 3, 5);
  EXPECT_EQ(t.truth[0], (std::vector<std::size_t>{3}));
  EXPECT_TRUE(t.truth[1].empty());
  EXPECT_EQ(t.truth[2], (std::vector<std::size_t>{1, 4}));
  EXPECT_EQ(default_localization_tolerance(pairs), 0U);
  constexpr std::string_view keywords[] = {"same-index"};
  EXPECT_EQ(default_localization_tolerance(read_ground_truth("same-index", keywords, std::nullopt)), 2U);
  RgbImage m(5, 3);  // 3 query rows x 5 map columns
  std::fill_n(m.at(3, 0), 3, std::uint8_t{255});
  std::fill_n(m.at(1, 2), 3, std::uint8_t{255});
  const auto image = dir.path / "q.png";
  plot::write_png(image, m);
  const auto from_image = localization_truth(read_ground_truth(image.string(), {}, std::nullopt), 3, 5);
  EXPECT_EQ(from_image.truth[0], (std::vector<std::size_t>{3}));
  EXPECT_EQ(from_image.truth[2], (std::vector<std::size_t>{1}));
  EXPECT_EQ(error_of([&] { localization_truth(read_ground_truth(image.string(), {}, std::nullopt), 5, 3); }),
            image.string() + ": is 3 x 5, expected 5 query rows x 3 map columns");
}

}  // namespace
}  // namespace seqtopo::pipeline
