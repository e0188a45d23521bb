// Reading images and video frames; corrupt files are reported by name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <random>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/image/image_io.hpp"

namespace seqtopo::image {
namespace {

namespace fs = std::filesystem;

using seqtopo::test_support::TempDir;

template <typename F>
void expect_error_naming(const fs::path& file, F&& f) {
  try {
    f();
    FAIL() << "expected an error for " << file;
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), file.string());
  }
}

TEST(LoadImage, RgbOrderAndSize) {
  TempDir dir;
  cv::Mat bgr(3, 5, CV_8UC3, cv::Scalar(10, 20, 30));  // B, G, R
  bgr.at<cv::Vec3b>(1, 2) = cv::Vec3b(200, 100, 50);
  const fs::path file = dir.path / "a.png";
  ASSERT_TRUE(cv::imwrite(file.string(), bgr));
  const RgbImage img = load_image(file);
  ASSERT_EQ(img.width, 5);
  ASSERT_EQ(img.height, 3);
  EXPECT_EQ(img.at(0, 0)[0], 30);
  EXPECT_EQ(img.at(0, 0)[2], 10);
  EXPECT_EQ(img.at(2, 1)[0], 50);
  EXPECT_EQ(img.at(2, 1)[1], 100);
  EXPECT_EQ(img.at(2, 1)[2], 200);

  cv::Mat grey(4, 4, CV_8UC1, cv::Scalar(77));
  ASSERT_TRUE(cv::imwrite((dir.path / "g.png").string(), grey));
  const RgbImage g = load_image(dir.path / "g.png");
  EXPECT_EQ(g.at(3, 3)[0], 77);
  EXPECT_EQ(g.at(3, 3)[2], 77);
}

TEST(LoadImage, CorruptFilesAreNamed) {
  TempDir dir;
  const fs::path garbage = dir.path / "garbage.png", empty = dir.path / "empty.jpg", cut = dir.path / "cut.jpg";
  std::ofstream(garbage) << "this is not a picture";
  std::ofstream(empty).flush();
  cv::Mat noise(64, 64, CV_8UC3);
  cv::randu(noise, 0, 255);
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", noise, jpeg));
  std::ofstream(cut, std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), static_cast<std::streamsize>(jpeg.size() / 2));
  expect_error_naming(garbage, [&] { load_image(garbage); });
  expect_error_naming(empty, [&] { load_image(empty); });
  expect_error_naming(cut, [&] { load_image(cut); });
  expect_error_naming(dir.path / "missing.png", [&] { load_image(dir.path / "missing.png"); });
  expect_error_naming(dir.path, [&] { load_image(dir.path); });  // a folder, not the stream library's text
}

TEST(Video, EveryKthFrame) {
  TempDir dir;
  const fs::path file = dir.path / "walk.avi";
  {
    cv::VideoWriter writer(file.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, cv::Size(32, 24));
    ASSERT_TRUE(writer.isOpened());
    for (int k = 0; k < 10; ++k) writer.write(cv::Mat(24, 32, CV_8UC3, cv::Scalar(k * 25, k * 25, k * 25)));
  }
  std::vector<std::size_t> indices;
  std::vector<int> brightness;
  for_each_video_frame(file, 3, [&](std::size_t index, const RgbImage& frame) {
    indices.push_back(index);
    EXPECT_EQ(frame.width, 32);
    EXPECT_EQ(frame.height, 24);
    brightness.push_back(frame.at(16, 12)[1]);
  });
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 3, 6, 9}));
  for (std::size_t k = 0; k < brightness.size(); ++k) EXPECT_NEAR(brightness[k], static_cast<int>(indices[k]) * 25, 6);
  const auto count = video_frame_count(file);
  ASSERT_TRUE(count.has_value());
  EXPECT_EQ(*count, 10U);
  EXPECT_THROW(for_each_video_frame(file, 0, [](std::size_t, const RgbImage&) {}), std::invalid_argument);
}

// A video cut short (a copy that stopped, a full disk) still opens and yields its first frames: the pass says
// how many it read against those the container announced, and a warning names the file; the whole file none.
TEST(Video, OneEndingBeforeTheFramesItAnnouncesIsWarnedOf) {
  TempDir dir;
  const fs::path file = dir.path / "whole.avi", cut = dir.path / "cut.avi";
  {
    cv::VideoWriter writer(file.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, cv::Size(64, 48));
    ASSERT_TRUE(writer.isOpened());
    cv::Mat frame(48, 64, CV_8UC3);
    for (int k = 0; k < 40; ++k) {
      cv::randu(frame, cv::Scalar::all(0), cv::Scalar::all(255));
      writer.write(frame);
    }
  }
  const auto whole = for_each_video_frame(file, 1, [](std::size_t, const RgbImage&) {});
  EXPECT_EQ(whole.read, 40U);
  ASSERT_TRUE(whole.announced.has_value());
  EXPECT_EQ(video_ended_early(file, whole), "");
  {
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const auto part = for_each_video_frame(cut, 1, [](std::size_t, const RgbImage&) {});
  EXPECT_LT(part.read, 30U);
  ASSERT_TRUE(part.announced.has_value());
  EXPECT_EQ(*part.announced, 40U);
  EXPECT_EQ(video_ended_early(cut, part), "warning: " + cut.string() + ": the video ended after " +
                                              std::to_string(part.read) +
                                              " of the 40 frames it announces (truncated or damaged?); only those "
                                              "are mapped");
}

TEST(Video, UnreadableIsNamed) {
  TempDir dir;
  const fs::path file = dir.path / "broken.mp4";
  std::ofstream(file) << "not a video";
  expect_error_naming(file, [&] { for_each_video_frame(file, 1, [](std::size_t, const RgbImage&) {}); });
  expect_error_naming(dir.path / "missing.avi", [&] { video_frame_count(dir.path / "missing.avi"); });
}

}  // namespace
}  // namespace seqtopo::image
