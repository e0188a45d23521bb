// The command line as a user meets it: bad input gives one line `seqtopo: error: <subject>: <what>`,
// a non-zero exit and no output file; good input gives the same alignments as the library.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "seqtopo/io/npy.hpp"

namespace {
namespace fs = std::filesystem;

struct Outcome {
  int status = 0;
  std::string err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("seqtopo-cli-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome run(const std::string& args) {
    const std::string err_file = (dir_ / "stderr.txt").string();
    const std::string command = std::string(SEQTOPO_CLI) + " " + args + " >/dev/null 2>" + err_file + " </dev/null";
    Outcome o;
    const int raw = std::system(command.c_str());
    o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    std::ifstream in(err_file);
    o.err.assign((std::istreambuf_iterator<char>(in)), {});
    return o;
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  void expect_clean_error(const Outcome& o, const std::string& subject) {
    EXPECT_NE(o.status, 0);
    EXPECT_NE(o.status, -1) << "must exit, not crash";
    ASSERT_FALSE(o.err.empty());
    EXPECT_EQ(o.err.rfind("seqtopo: error: " + subject, 0), 0U) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "one line: " << o.err;
  }
  fs::path dir_;
};

TEST_F(Cli, AlignRejectsBadInputWithOneLineAndNoOutput) {
  const auto a = write("a.fa", ">a\nACGTACGT\n");
  const auto json = dir_ / "out.json";
  expect_clean_error(run("align --a " + (dir_ / "missing.fa").string() + " --json " + json.string()), "--a");
  expect_clean_error(run("align --a " + write("empty.fa", "").string() + " --json " + json.string()),
                     (dir_ / "empty.fa").string());
  expect_clean_error(run("align --a " + a.string() + " --gap -1 --json " + json.string()), "--gap");
  expect_clean_error(run("align --a " + a.string() + " --cap 0 --json " + json.string()), "--cap");
  expect_clean_error(run("align --scores " + write("bad.npy", "garbage").string() + " --json " + json.string()),
                     (dir_ / "bad.npy").string());
  // a non-square matrix cannot be a self alignment
  seqtopo::io::write_npy(dir_ / "rect.npy", seqtopo::DenseMatrix<float>(2, 3, 1.0F));
  expect_clean_error(run("align --self --scores " + (dir_ / "rect.npy").string() + " --json " + json.string()),
                     (dir_ / "rect.npy").string());
  expect_clean_error(run("align --no-such-option"), "");
  EXPECT_FALSE(fs::exists(json)) << "no output may be written on error";
}

TEST_F(Cli, AlignWritesAlignmentsJson) {
  const auto a = write("a.fa", ">a\nTTTTACGTACGTGGGG\n");
  const auto b = write("b.fa", ">b\nCCACGTACGTCC\n");
  const auto json = dir_ / "out.json";
  const auto o = run("align --a " + a.string() + " --b " + b.string() +
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
  for (const auto& e : fs::directory_iterator(dir_))
    temporaries += e.path().string().find(".tmp.") != std::string::npos;
  EXPECT_EQ(temporaries, 0U);
}

TEST_F(Cli, HelpExitsZero) {
  EXPECT_EQ(run("--help").status, 0);
  EXPECT_EQ(run("align --help").status, 0);
  EXPECT_NE(run("").status, 0) << "a subcommand is required";
}

}  // namespace
