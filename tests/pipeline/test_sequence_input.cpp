// Natural order, folder listing and input kinds.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/plot/png.hpp"

namespace seqtopo::pipeline {
namespace {

namespace fs = std::filesystem;

using seqtopo::test_support::TempDir;

TEST(NaturalSort, NumbersByValue) {
  std::vector<std::string> names{"10.jpg", "2.jpg", "1.jpg", "img-010.png", "img-9.png", "B.png", "a.png", "1.jpg.bak"};
  std::sort(names.begin(), names.end(), [](const auto& a, const auto& b) { return natural_less(a, b); });
  // glibc's strverscmp: bytes in byte order ("B" < "a"), a run with leading zeros before the others.
  EXPECT_EQ(names, (std::vector<std::string>{"1.jpg", "1.jpg.bak", "2.jpg", "10.jpg", "B.png", "a.png", "img-010.png",
                                             "img-9.png"}));
  EXPECT_TRUE(natural_less("run_9.db3", "run_10.db3"));
  EXPECT_TRUE(natural_less("run_2.mcap", "run_11.mcap"));
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
  fs::create_directory(dir.path / "notes");  // a folder without an image's name is not looked at
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

// Issue #18 (a): an entry that has an image's name but cannot be read is an error naming it, or, with
// skip_unreadable, left out and listed.
TEST(ListImages, UnreadableEntriesAreErrorsNamingThem) {
  TempDir dir;
  plot::write_png(dir.path / "1.png", RgbImage(4, 4, 100));
  plot::write_png(dir.path / "3.png", RgbImage(4, 4, 200));
  const auto expect_refused = [&](const fs::path& entry, const std::string& what) {
    try {
      list_images(dir.path);
      ADD_FAILURE() << "no error for " << entry;
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), entry.string());
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    const ImageListing skipped = list_images(dir.path, {.skip_unreadable = true});
    ASSERT_EQ(skipped.files.size(), 2U);
    ASSERT_EQ(skipped.skipped.size(), 1U);
    EXPECT_EQ(skipped.skipped[0].first, entry);
    fs::remove(entry);
  };
  fs::create_symlink(dir.path / "missing.png", dir.path / "2.png");
  expect_refused(dir.path / "2.png", "a dangling symbolic link");
  fs::create_symlink(dir.path / "loop.png", dir.path / "loop.png");
  expect_refused(dir.path / "loop.png", "a looping symbolic link");
  fs::create_directory(dir.path / "4.png");
  expect_refused(dir.path / "4.png", "a folder");
  ASSERT_EQ(::mkfifo((dir.path / "5.png").c_str(), 0600), 0);
  expect_refused(dir.path / "5.png", "a FIFO");
  // A corrupt file is refused when it is decoded (naming it); --skip-unreadable decodes while listing.
  dir.write("6.png", "not a png");
  const ImageListing skipped = list_images(dir.path, {.skip_unreadable = true});
  ASSERT_EQ(skipped.skipped.size(), 1U);
  EXPECT_EQ(skipped.skipped[0].first, dir.path / "6.png");
  EXPECT_EQ(list_images(dir.path).size(), 3U);  // not decoded without the option
  try {
    compute_similarity(SequenceInput(dir.path));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), (dir.path / "6.png").string());
  }
  SequenceInput skip(dir.path);
  skip.skip_unreadable = true;
  std::vector<std::string> notes;
  SimilarityConfig config;
  config.note = [&](std::string_view text) { notes.emplace_back(text); };
  EXPECT_EQ(compute_similarity(skip, config).similarity.rows, 2U);
  ASSERT_EQ(notes.size(), 1U);
  EXPECT_NE(notes[0].find("6.png"), std::string::npos) << notes[0];
}

TEST(ListImages, RecursiveInNaturalOrderOfRelativePaths) {
  TempDir dir;
  for (const char* folder : {"a", "b", "b/c", ".git"}) fs::create_directories(dir.path / folder);
  for (const char* name : {"a/10.png", "a/2.png", "b.png", "b/1.png", "b/c/1.png", ".git/x.png", "0.png"}) {
    dir.touch(name);
  }
  const auto listing = list_images(dir.path, {.recursive = true});
  std::vector<std::string> names;
  for (const auto& f : listing.files) names.push_back(image_name(dir.path, f, true));
  // Folder name by folder name: the folder "b" sorts before the file "b.png".
  EXPECT_EQ(names, (std::vector<std::string>{"0.png", "a/2.png", "a/10.png", "b/1.png", "b/c/1.png", "b.png"}));
  EXPECT_EQ(list_images(dir.path).size(), 2U);  // without recursion: 0.png and b.png
}

// Issue #18 (a): images of different sizes are an error for the joint histogram, which does not resize, and
// a warning for the patch descriptor, which does.
TEST(ImageSizes, DifferentSizesRefusedOrWarned) {
  TempDir dir;
  plot::write_png(dir.path / "1.png", RgbImage(16, 12, 10));
  plot::write_png(dir.path / "2.png", RgbImage(16, 12, 90));
  plot::write_png(dir.path / "3.png", RgbImage(20, 12, 180));
  SimilarityConfig config;
  std::vector<std::string> notes;
  config.note = [&](std::string_view text) { notes.emplace_back(text); };
  config.descriptor = Descriptor::joint_histogram;
  try {
    compute_similarity(SequenceInput(dir.path), config);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), (dir.path / "3.png").string());
    EXPECT_NE(std::string(e.what()).find("20 x 12 pixels, the first image 1.png is 16 x 12"), std::string::npos)
        << e.what();
  }
  config.descriptor = Descriptor::patch;
  EXPECT_EQ(compute_similarity(SequenceInput(dir.path), config).similarity.rows, 3U);
  ASSERT_EQ(notes.size(), 1U);
  EXPECT_NE(notes[0].find("patch descriptor resizes every image"), std::string::npos) << notes[0];
}

// Issue 47, defect 5: sessions (or the two sides of a comparison: map and query) of different image sizes were
// compared without a word (every query frame "not in the map"), while the same mix inside one folder is an error.
// The same error across sessions and sides for the joint histogram; the patch descriptor resizes and goes on.
TEST(ImageSizes, SessionsAndSidesOfDifferentSizes) {
  TempDir dir;
  for (const auto& [folder, width] : {std::pair{"small", 16}, std::pair{"large", 20}}) {
    fs::create_directories(dir.path / folder);
    for (int k = 0; k < 3; ++k) {
      plot::write_png(dir.path / folder / (std::to_string(k) + ".png"), RgbImage(width, 12, 60 * k + 10));
    }
  }
  const SequenceInput small(dir.path / "small"), large(dir.path / "large");
  SimilarityConfig config;
  config.descriptor = Descriptor::joint_histogram;
  const auto expect_refused = [&](const auto& call) {
    try {
      call();
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), (dir.path / "large").string());
      EXPECT_NE(std::string(e.what()).find("its images are 20 x 12 pixels, those of " + (dir.path / "small").string() +
                                           " 16 x 12: the joint-histogram descriptor does not resize"),
                std::string::npos)
          << e.what();
    }
  };
  const std::vector<SequenceInput> sessions{small, large};
  expect_refused([&] { compute_similarity(sessions, config); });
  expect_refused([&] { compute_similarity(small, large, config); });
  EXPECT_EQ(compute_similarity(small, small, config).similarity.rows, 3U);
  config.descriptor = Descriptor::patch;
  EXPECT_EQ(compute_similarity(sessions, config).similarity.rows, 6U);
  EXPECT_EQ(compute_similarity(small, large, config).similarity.cols, 3U);
}

TEST(SequenceInput, SelectedFramesOnly) {
  TempDir dir;
  for (int k = 0; k < 5; ++k) plot::write_png(dir.path / (std::to_string(k) + ".png"), RgbImage(8, 8, 40 * k));
  SequenceInput input(dir.path);
  input.frames = {0, 2, 3};
  SimilarityConfig config;
  config.descriptor = Descriptor::patch;
  const auto r = compute_similarity(input, config);
  EXPECT_EQ(r.frame_names, (std::vector<std::string>{"0.png", "2.png", "3.png"}));
  input.frames = {0, 7};
  EXPECT_THROW(compute_similarity(input, config), InputError);
  // Two sessions: one sequence, names prefixed by the session.
  const std::vector<SequenceInput> sessions{SequenceInput(dir.path), SequenceInput(dir.path)};
  const auto two = compute_similarity(sessions, config);
  EXPECT_EQ(two.similarity.rows, 10U);
  EXPECT_EQ(two.session_rows, (std::vector<std::size_t>{5, 5}));
  EXPECT_EQ(two.frame_names[5], dir.path.filename().string() + "/0.png");
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
