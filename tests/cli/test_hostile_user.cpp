// The findings of issue #18's test as a hostile user, each replayed on the command line: bad option values
// (1), a wrapping .npy size check (8) and the config file and option checks (9). Every bad input gives one
// line `seqtopo: error: <file or option>: <problem>`, a non-zero exit, and no output folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/io/npy.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_cli;
using seqtopo::test_support::run_command;

class HostileUser : public ::testing::Test {
 protected:
  // One error line naming `subject` first, the last on stderr (progress lines of the stages begun may come before
  // it), exit `status` (2: the command line, 1: a file), and no --out folder.
  void expect_error(const CommandResult& r, const std::string& subject, int status, const std::string& fragment = {}) {
    EXPECT_EQ(r.status, status) << r.err;
    ASSERT_FALSE(r.err.empty());
    ASSERT_EQ(r.err.back(), '\n') << r.err;
    const auto start = r.err.rfind('\n', r.err.size() - 2);
    const std::string last = r.err.substr(start == std::string::npos ? 0 : start + 1);
    EXPECT_EQ(last.rfind("seqtopo: error: " + subject + ": ", 0), 0U) << r.err;
    std::size_t errors = 0;
    for (auto at = r.err.find("error:"); at != std::string::npos; at = r.err.find("error:", at + 1)) ++errors;
    EXPECT_EQ(errors, 1U) << r.err;
    if (!fragment.empty()) {
      EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(out())) << "the output folder was made";
  }
  fs::path out() const { return dir_.path / "out"; }
  std::string out_arg() const { return " --out " + out().string(); }
  std::string small_similarity() const {
    seqtopo::DenseMatrix<float> s(40, 40, 0.0F);
    for (std::size_t i = 0; i < 40; ++i) s(i, i) = 1.0F;
    seqtopo::io::write_npy(dir_.path / "s.npy", s);
    return (dir_.path / "s.npy").string();
  }
  const seqtopo::test_support::TempDir dir_;
};

// Finding 1: `--contrast-offset nan` wrote an all-NaN scores.npy, `--min-separation -1` became 2^64 - 1,
// `--kappa 3x` ran with kappa = 3; all exited 0.
TEST_F(HostileUser, BadOptionValuesAreRefusedBeforeAnyWork) {
  const std::string s = small_similarity();
  expect_error(run_cli("map " + s + " --contrast-offset nan" + out_arg()), "--contrast-offset", 2, "'nan'");
  expect_error(run_cli("map " + s + " --min-separation -1" + out_arg()), "--min-separation", 2, "'-1'");
  expect_error(run_cli("map " + s + " --kappa 3x" + out_arg()), "--kappa", 2, "'3x'");
  expect_error(run_cli("map " + s + " --gap inf" + out_arg()), "--gap", 2);
  expect_error(run_cli("localize --map " + s + " --contrast-window -3" + out_arg()), "--contrast-window", 2);
  expect_error(run_cli("similarity " + s + " --kappa -1" + out_arg()), "--kappa", 2);
}

// Finding 8: a header with shape (2^61 - 1, 1) of float64 wrapped offset + count * 8 past the truncation check
// and the user read "seqtopo: error: out of memory", naming no file.
TEST_F(HostileUser, NpyWhoseSizeWrapsNamesTheFile) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (2305843009213693951, 1), }";
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string bytes = "\x93NUMPY";
  bytes.push_back('\x01');
  bytes.push_back('\x00');
  bytes.push_back(static_cast<char>(dict.size() & 0xFFU));
  bytes.push_back(static_cast<char>(dict.size() >> 8U));
  bytes.append(dict);
  bytes.append(64, '\0');
  const std::string npy = dir_.write("huge.npy", bytes).string();
  for (const std::string& args : {"align --scores " + npy + " --json " + (dir_.path / "out.json").string(),
                                  "localize --map " + npy + " --input-kind similarity" + out_arg(),
                                  "map " + npy + out_arg(), "similarity " + npy + out_arg()}) {
    SCOPED_TRACE(args);
    expect_error(run_cli(args), npy, 1, "truncated");
  }
  EXPECT_FALSE(fs::exists(dir_.path / "out.json"));
}

// Finding 9: `--config DIR` was silently ignored; unknown keys and JSON configs gave errors that did not name the
// file.
TEST_F(HostileUser, ConfigFileErrorsNameTheFileAndLine) {
  const std::string s = small_similarity();
  const auto map = [&](const std::string& config) { return run_cli("map " + s + " --config " + config + out_arg()); };
  expect_error(map(dir_.path.string()), dir_.path.string(), 1, "a folder, not a config file");
  const auto unknown = dir_.write("unknown.yaml", "gap: 1\n# a comment\nnope: 3\n").string();
  expect_error(map(unknown), unknown + ":3", 1, "unknown option 'nope' for seqtopo map");
  const auto json = dir_.write("config.json", "{\n  \"gap\": 1.5\n}\n").string();
  expect_error(map(json), json, 1, "JSON");
  const auto nan = dir_.write("nan.yaml", "gap: nan\n").string();
  expect_error(map(nan), nan + ":1", 1, "--gap: expected a finite number >= 0, got 'nan'");
  // A UTF-8 byte-order mark (an editor's) before the first name is not part of it.
  const auto marked = dir_.write("marked.yaml", "\xEF\xBB\xBFgap: nan\n").string();
  expect_error(map(marked), marked + ":1", 1, "--gap: expected a finite number >= 0, got 'nan'");
  const auto flag = dir_.write("flag.yaml", "no-reverse: yes\n").string();
  expect_error(map(flag), flag + ":1", 1, "true or false");
  const auto nested = dir_.write("nested.yaml", "config: other.yaml\n").string();
  expect_error(map(nested), nested + ":1", 1);
  const auto garbled = dir_.write("garbled.yaml", "gap 1\n").string();
  expect_error(map(garbled), garbled + ":1", 1, "name: value");
  expect_error(map((dir_.path / "missing.yaml").string()), (dir_.path / "missing.yaml").string(), 1);
  // a nested subcommand's options are the ones checked
  const auto scale = dir_.write("scale.yaml", "sizes: 1000,x\n").string();
  expect_error(run_cli("bench scale --config " + scale), scale + ":1", 1, "--sizes");
  // every value is checked, also the ones the command line overrides
  const auto negative =
      dir_.write("negative.yaml", "gap: 1.5\nno-reverse: true\nthreads: 1\nmin-separation: -1\n").string();
  expect_error(map(negative), negative + ":4", 1, "--min-separation");
  const auto fine = dir_.write("fine.yaml", "gap: nan\n").string();
  const auto r = run_cli("map " + s + " --config " + fine + " --gap 1" + out_arg());
  EXPECT_NE(r.status, 0) << "the file's values are checked even when the command line overrides them";
}

// Finding 9: `--every 0` and `--kappa inf` failed only after --out was created.
TEST_F(HostileUser, EveryZeroAndKappaInfFailBeforeTheOutputFolder) {
  const std::string s = small_similarity();
  expect_error(run_cli("map " + s + " --every 0" + out_arg()), "--every", 2);
  expect_error(run_cli("map " + s + " --kappa inf" + out_arg()), "--kappa", 2);
  expect_error(run_cli("similarity " + s + " --every 0" + out_arg()), "--every", 2);
  expect_error(run_cli("localize --map " + s + " --every 0" + out_arg()), "--every", 2);
  expect_error(run_cli("localize --map " + s + " --kappa inf" + out_arg()), "--kappa", 2);
}

// Finding 9: `--threads 10000` was not capped. Beyond 4096 it is refused; up to it, no more threads than cores run.
// The kind of a .npy comes from its name: a similarity matrix saved as s.npy was mapped as 40 descriptors
// without a word. It still is (a square array can be descriptors), but a symmetric one is said to be.
TEST_F(HostileUser, ASymmetricSquareNpyReadAsDescriptorsIsSaid) {
  const std::string s = small_similarity();
  const auto as_descriptors = run_cli("map " + s + out_arg());
  ASSERT_EQ(as_descriptors.status, 0) << as_descriptors.err;
  EXPECT_NE(as_descriptors.err.find(s + ": a symmetric 40 x 40 array, read as descriptors"), std::string::npos)
      << as_descriptors.err;
  fs::remove_all(out());
  const auto told = run_cli("map " + s + " --input-kind similarity" + out_arg());
  ASSERT_EQ(told.status, 0) << told.err;
  EXPECT_EQ(told.err.find("read as descriptors"), std::string::npos) << told.err;
}

TEST_F(HostileUser, ThreadsAreCappedAtTheCores) {
  expect_error(run_cli("map --threads 10000" + out_arg()), "--threads", 2, "[0, 4096]");
  // the process's threads, sampled while it maps the bundled corridor with --threads 4096
  std::string script = "'";
  script.append(SEQTOPO_CLI);
  script.append("' map --threads 4096 --out '").append(out().string());
  script.append("' 2>/dev/null & pid=$!; most=0; while kill -0 $pid 2>/dev/null; do ");
  script.append("n=$(ls /proc/$pid/task 2>/dev/null | wc -l); [ \"$n\" -gt \"$most\" ] && most=$n; ");
  script.append("done; wait $pid; echo \"$? $most\"");
  const auto r = run_command(script);
  int status = -1, most = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "%d %d", &status, &most), 2) << r.out;
  EXPECT_EQ(status, 0);
  const int cores = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  EXPECT_GT(most, 0);
  // OpenMP's pool and the report's image decoding are at most one thread a core each; the main and progress
  // threads come on top.
  EXPECT_LE(most, 2 * cores + 4) << "threads seen with --threads 4096 on " << cores << " cores";
}

}  // namespace
