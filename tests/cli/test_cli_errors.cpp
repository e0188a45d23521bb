// The command line as a user meets it: bad input gives one line `seqtopo: error: <subject>: <what>`,
// a non-zero exit and no output file; good input gives the same alignments as the library.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/io/npy.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_cli;

class Cli : public ::testing::Test {
 protected:
  static void expect_clean_error(const CommandResult& o, const std::string& subject) {
    EXPECT_NE(o.status, 0);
    EXPECT_NE(o.status, -1) << "must exit, not crash";
    ASSERT_FALSE(o.err.empty());
    EXPECT_EQ(o.err.rfind("seqtopo: error: " + subject, 0), 0U) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "one line: " << o.err;
  }
  const seqtopo::test_support::TempDir dir_;
};

TEST_F(Cli, AlignRejectsBadInputWithOneLineAndNoOutput) {
  const auto a = dir_.write("a.fa", ">a\nACGTACGT\n");
  const auto json = dir_.path / "out.json";
  expect_clean_error(run_cli("align --a " + (dir_.path / "missing.fa").string() + " --json " + json.string()), "--a");
  expect_clean_error(run_cli("align --a " + dir_.write("empty.fa", "").string() + " --json " + json.string()),
                     (dir_.path / "empty.fa").string());
  expect_clean_error(run_cli("align --a " + a.string() + " --gap -1 --json " + json.string()), "--gap");
  expect_clean_error(run_cli("align --a " + a.string() + " --cap 0 --json " + json.string()), "--cap");
  expect_clean_error(
      run_cli("align --scores " + dir_.write("bad.npy", "garbage").string() + " --json " + json.string()),
      (dir_.path / "bad.npy").string());
  // a non-square matrix cannot be a self alignment
  seqtopo::io::write_npy(dir_.path / "rect.npy", seqtopo::DenseMatrix<float>(2, 3, 1.0F));
  expect_clean_error(run_cli("align --self --scores " + (dir_.path / "rect.npy").string() + " --json " + json.string()),
                     (dir_.path / "rect.npy").string());
  expect_clean_error(run_cli("align --no-such-option"), "");
  EXPECT_FALSE(fs::exists(json)) << "no output may be written on error";
}

TEST_F(Cli, AlignWritesAlignmentsJson) {
  const auto a = dir_.write("a.fa", ">a\nTTTTACGTACGTGGGG\n");
  const auto b = dir_.write("b.fa", ">b\nCCACGTACGTCC\n");
  const auto json = dir_.path / "out.json";
  const auto o = run_cli("align --a " + a.string() + " --b " + b.string() +
                         " --match 2 --mismatch -1 --gap 1 --max-alignments 3 --json " + json.string());
  ASSERT_EQ(o.status, 0) << o.err;
  std::ifstream in(json);
  const auto doc = nlohmann::json::parse(in);
  ASSERT_FALSE(doc["alignments"].empty());
  const auto& best = doc["alignments"][0];
  EXPECT_EQ(best["score"].get<double>(), 16.0);  // ACGTACGT matched whole: 8 x 2
  EXPECT_EQ(best["a_begin"].get<int>(), 4);
  EXPECT_EQ(best["a_end"].get<int>(), 12);
  EXPECT_EQ(best["b_begin"].get<int>(), 2);
  EXPECT_EQ(best["direction"].get<std::string>(), "forward");
  EXPECT_EQ(best["pairs"].size(), 8U);
  std::size_t temporaries = 0;
  for (const auto& e : fs::directory_iterator(dir_.path))
    temporaries += e.path().string().find(".tmp.") != std::string::npos;
  EXPECT_EQ(temporaries, 0U);
}

TEST_F(Cli, HelpExitsZero) {
  EXPECT_EQ(run_cli("--help").status, 0);
  EXPECT_EQ(run_cli("align --help").status, 0);
  EXPECT_NE(run_cli("").status, 0) << "a subcommand is required";
}

}  // namespace
