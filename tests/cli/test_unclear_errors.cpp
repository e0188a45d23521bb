// The unclear errors of issue #47, each replayed on the command line: one line on stderr naming the right file or
// option in the user's words, the exit status of its kind (2: the command line, 1: a file), before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/plot/png.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_cli;

class UnclearErrors : public ::testing::Test {
 protected:
  // The last stderr line is `seqtopo: error: SUBJECT: ...FRAGMENT...`, the only error line; exit `status`.
  static void expect_error(const CommandResult& r, const std::string& subject, int status,
                           const std::string& fragment) {
    EXPECT_EQ(r.status, status) << r.err;
    ASSERT_FALSE(r.err.empty());
    std::string text = r.err;
    if (text.back() == '\n') text.pop_back();
    const std::string last = text.substr(text.rfind('\n') + 1);
    EXPECT_EQ(last.rfind("seqtopo: error: " + subject + ": ", 0), 0U) << r.err;
    EXPECT_NE(last.find(fragment), std::string::npos) << r.err;
    std::size_t errors = 0;
    for (auto at = r.err.find("error:"); at != std::string::npos; at = r.err.find("error:", at + 1)) ++errors;
    EXPECT_EQ(errors, 1U) << r.err;
  }
  std::string matrix(const std::string& name, std::size_t rows, std::size_t cols) const {
    seqtopo::DenseMatrix<float> m(rows, cols, 0.0F);
    for (std::size_t i = 0; i < rows; ++i) {
      for (std::size_t j = 0; j < cols; ++j) m(i, j) = static_cast<float>((i * 7 + j * 3) % 11);
    }
    seqtopo::io::write_npy(dir_.path / name, m);
    return (dir_.path / name).string();
  }
  std::string similarity() const {
    seqtopo::DenseMatrix<float> s(40, 40, 0.0F);
    for (std::size_t i = 0; i < 40; ++i) s(i, i) = 1.0F;
    seqtopo::io::write_npy(dir_.path / "s.npy", s);
    return (dir_.path / "s.npy").string();
  }
  std::string out() const { return " --out " + (dir_.path / "out").string(); }
  const seqtopo::test_support::TempDir dir_;
};

TEST_F(UnclearErrors, AnUnknownCommandIsSaidAsSuch) {
  const auto r = run_cli("frobnicate --out x");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("seqtopo: error: unknown command 'frobnicate' (commands: align, ", 0), 0U) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.find("A subcommand is required"), std::string::npos) << r.err;
}

TEST_F(UnclearErrors, OdometryGateNumbersAreACommandLineError) {
  expect_error(run_cli("map " + similarity() + " --odometry-gate inf,inf" + out()), "--odometry-gate", 2, "'inf'");
  expect_error(run_cli("map " + similarity() + " --odometry-gate 1" + out()), "--odometry-gate", 2, "BASE,DRIFT");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
}

TEST_F(UnclearErrors, GtRadiusAloneIsRefusedNotIgnored) {
  expect_error(run_cli("map " + similarity() + " --gt-radius 2" + out()), "--gt-radius", 1, "--ground-truth");
  expect_error(run_cli("map " + similarity() + " --online --gt-radius 2" + out()), "--gt-radius", 1, "--ground-truth");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
}

TEST_F(UnclearErrors, MinSeparationBeyondAnySequenceIsRefusedUpFront) {
  const auto r = run_cli("map " + similarity() + " --min-separation 18446744073709551615" + out());
  expect_error(r, "--min-separation", 2, "18446744073709551615");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
}

TEST_F(UnclearErrors, ThinnedToOneImageSaysWhichOptionKeptOne) {
  const std::string d = matrix("descriptors.npy", 3, 8);
  expect_error(run_cli("map " + d + " --every 3" + out()), d, 1, "--every 3 kept 1");
}

TEST_F(UnclearErrors, SimilarityAgainstNamesTheSequenceThatDisagrees) {
  const std::string a = matrix("a_descriptors.npy", 6, 8), b = matrix("b_descriptors.npy", 5, 9);
  expect_error(run_cli("similarity " + a + " --against " + b + out()), b, 1, "9 values");
}

TEST_F(UnclearErrors, AFolderIsNotCalledAnEmptyFile) {
  fs::create_directory(dir_.path / "poses");
  const auto r = run_cli("map " + similarity() + " --odometry " + (dir_.path / "poses").string() + out());
  expect_error(r, (dir_.path / "poses").string(), 1, "a folder, not a pose file");
}

// `#` inside a quoted value is part of it; outside quotes it begins a comment.
TEST_F(UnclearErrors, HashInsideQuotesInAConfigIsPartOfTheValue) {
  const fs::path target = dir_.path / "run#2";
  std::ofstream(dir_.path / "config.yaml") << "out: \"" << target.string() << "\"  # the second run\n"
                                           << "threads: 1 # one\n";
  const auto r = run_cli("map " + similarity() + " --config " + (dir_.path / "config.yaml").string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(target / "map.json")) << r.err;
}

// libpng's own warnings ("libpng warning: tEXt: CRC error") do not reach stderr: an image with a damaged
// ancillary chunk decodes, and stderr holds only seqtopo's lines.
TEST_F(UnclearErrors, LibpngWarningsDoNotReachStderr) {
  const fs::path folder = dir_.path / "images";
  fs::create_directory(folder);
  for (int k = 0; k < 3; ++k) {
    seqtopo::RgbImage image(24, 16);
    for (std::size_t b = 0; b < image.pixels.size(); ++b) image.pixels[b] = static_cast<std::uint8_t>(b * (k + 3));
    const fs::path png = folder / (std::to_string(k) + ".png");
    seqtopo::plot::write_png(png, image);
    std::string bytes = seqtopo::test_support::read_file(png);
    // A tEXt chunk with a wrong CRC before IEND (the last 12 bytes): libpng warns and skips it.
    const std::string text = "Comment";
    std::string chunk("\0\0\0", 3);
    chunk += static_cast<char>(text.size());
    chunk += "tEXt" + text + std::string("\x12\x34\x56\x78", 4);
    bytes.insert(bytes.size() - 12, chunk);
    std::ofstream(png, std::ios::binary | std::ios::trunc) << bytes;
  }
  const auto r = run_cli("fingerprint " + folder.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("libpng"), std::string::npos) << r.err;
}

}  // namespace
