// Natural order, folder listing and input kinds.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"

namespace seqtopo::pipeline {
namespace {

namespace fs = std::filesystem;

using seqtopo::test_support::TempDir;

TEST(NaturalSort, NumbersByValue) {
  std::vector<std::string> names{"10.jpg", "2.jpg", "1.jpg", "img-010.png", "img-9.png", "B.png", "a.png", "1.jpg.bak"};
  std::sort(names.begin(), names.end(), [](const auto& a, const auto& b) { return natural_less(a, b); });
  EXPECT_EQ(names, (std::vector<std::string>{"1.jpg", "1.jpg.bak", "2.jpg", "10.jpg", "a.png", "B.png", "img-9.png",
                                             "img-010.png"}));
  EXPECT_TRUE(natural_less("images-00010.png", "images-00020.png"));
  EXPECT_TRUE(natural_less("frame2", "frame10"));
  EXPECT_FALSE(natural_less("frame10", "frame2"));
  // A strict weak order: equal-by-value names are still ordered one way only.
  EXPECT_NE(natural_less("07", "7"), natural_less("7", "07"));
  EXPECT_FALSE(natural_less("x", "x"));
}

TEST(ListImages, SortedImagesOnly) {
  TempDir dir;
  for (const char* name : {"10.jpg", "2.JPG", "1.png", "notes.txt", ".hidden.png", "ground_truth.bmp", "3.bmp"}) {
    dir.touch(name);
  }
  fs::create_directory(dir.path / "4.png");  // a folder is not an image
  const auto files = list_images(dir.path);
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(f.filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"1.png", "2.JPG", "3.bmp", "10.jpg"}));
}

TEST(ListImages, ErrorsNameTheFolder) {
  TempDir dir;
  dir.touch("readme.txt");
  try {
    list_images(dir.path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), dir.path.string());
  }
  EXPECT_THROW(list_images(dir.path / "missing"), InputError);
}

TEST(InputKind, ParseAndResolve) {
  EXPECT_EQ(parse_input_kind("auto"), InputKind::automatic);
  EXPECT_EQ(parse_input_kind("video"), InputKind::video);
  EXPECT_EQ(parse_input_kind("similarity"), InputKind::similarity);
  EXPECT_THROW(parse_input_kind("movie"), std::invalid_argument);
  TempDir dir;
  dir.touch("similarity.npy");
  dir.touch("descriptors.npy");
  dir.touch("walk.mp4");
  EXPECT_EQ(resolve_input_kind({dir.path}), InputKind::images);
  EXPECT_EQ(resolve_input_kind({dir.path / "similarity.npy"}), InputKind::similarity);
  EXPECT_EQ(resolve_input_kind({dir.path / "descriptors.npy"}), InputKind::descriptors);
  EXPECT_EQ(resolve_input_kind({dir.path / "walk.mp4"}), InputKind::video);
  EXPECT_EQ(resolve_input_kind({dir.path / "walk.mp4", InputKind::descriptors}), InputKind::descriptors);
  EXPECT_THROW(resolve_input_kind({dir.path / "missing.mp4"}), InputError);
}

}  // namespace
}  // namespace seqtopo::pipeline
