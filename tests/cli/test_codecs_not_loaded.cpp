// PNG and JPEG are the image module's own: decoding and encoding them, and `seqtopo map` of a PNG folder or of
// descriptors, never open the OpenCV plugin (libseqtopo_codecs.so and its ~250 libraries).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "common/cli_run.hpp"
#include "common/npy_bytes.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/image/codecs.hpp"

namespace {

namespace fs = std::filesystem;
using seqtopo::test_support::TempDir;
namespace codecs = seqtopo::image::codecs;

constexpr const char* kPlugin = "libseqtopo_codecs";

std::string mapped_files() {
  std::ifstream maps("/proc/self/maps");
  return {std::istreambuf_iterator<char>(maps), std::istreambuf_iterator<char>()};
}

void write(const fs::path& file, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

TEST(CodecsNotLoaded, PngAndJpegInThisProcess) {
  ASSERT_EQ(mapped_files().find(kPlugin), std::string::npos) << "opened before the test";
  TempDir dir;
  cv::Mat bgr(17, 31, CV_8UC3), grey(9, 5, CV_8UC1);
  cv::randu(bgr, 0, 256);
  cv::randu(grey, 0, 256);
  for (const cv::Mat& m : {bgr, grey}) {
    const auto png = codecs::encode_png(m);
    const auto jpeg = codecs::encode_jpeg(m, 90);
    EXPECT_EQ(codecs::decode(png).size(), m.size());
    EXPECT_EQ(codecs::decode(jpeg).size(), m.size());
    write(dir.path / "x.png", png);
    write(dir.path / "x.jpg", jpeg);
    EXPECT_EQ(codecs::read_grey(dir.path / "x.png").size(), m.size());
    EXPECT_EQ(codecs::read_grey(dir.path / "x.jpg").size(), m.size());
  }
  EXPECT_EQ(mapped_files().find(kPlugin), std::string::npos);
}

// The dynamic loader's own account (LD_DEBUG=files names every object it opens) of two whole maps.
TEST(CodecsNotLoaded, MapOfPngsAndOfDescriptors) {
  TempDir dir;
  const fs::path folder = dir.path / "frames";
  fs::create_directory(folder);
  std::mt19937 rng(1);
  cv::Mat frame(32, 64, CV_8UC3);
  for (int k = 0; k < 40; ++k) {
    cv::randu(frame, 0, 256);
    char name[16];
    std::snprintf(name, sizeof name, "%03d.png", k);
    write(folder / name, codecs::encode_png(frame));
  }
  std::string npy = seqtopo::test_support::npy_v1_header("<f4", 40, 16);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 40 * 16; ++i) {
    const float v = u(rng);
    npy.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  std::ofstream(dir.path / "d.npy", std::ios::binary) << npy;
  for (const fs::path& input : {folder, dir.path / "d.npy"}) {
    const auto r =
        seqtopo::test_support::run_command("LD_DEBUG=files exec " + std::string(SEQTOPO_CLI) + " map " +
                                           input.string() + " --out " + (dir.path / "out").string() + " --threads 1");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("calling init"), std::string::npos) << "no loader output: " << r.err.substr(0, 200);
    EXPECT_EQ(r.err.find(kPlugin), std::string::npos) << input;
    fs::remove_all(dir.path / "out");
  }
}

}  // namespace
