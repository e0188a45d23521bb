// Ground truth files sized against the sequence (ground_truth.hpp): the images kept, or every frame of the
// recording --every thinned, and a clear error naming the file otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

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

}  // namespace
}  // namespace seqtopo::pipeline
