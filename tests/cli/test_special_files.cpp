// Endless and blocking files named explicitly (issue #47, finding 8): /dev/zero as every kind of input file and on
// the online stdin, a FIFO as an input or as a path on stdin. Each is one error line naming the file, never a run
// whose memory grows without bound nor one that waits forever. The commands run under a memory limit (except under
// AddressSanitizer) and a generous kill timer, only so that a regression fails instead of hanging the suite; no
// result depends on them.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/io/npy.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_command;

class SpecialFiles : public ::testing::Test {
 protected:
  // `seqtopo ARGS` under 2 GiB of address space; `redirect` is shell text (e.g. "< /dev/zero").
  // AddressSanitizer reserves terabytes of shadow address space, so under it the limit is left off.
  static CommandResult run(const std::string& args, const std::string& redirect = "") {
#if defined(__SANITIZE_ADDRESS__)
    const std::string limit;
#else
    const std::string limit = "ulimit -v 2097152; ";
#endif
    return run_command(limit + "exec timeout -s KILL 600 " + std::string(SEQTOPO_CLI) + " " + args + " " + redirect);
  }
  // One line on stderr, `seqtopo: error: SUBJECT: ...FRAGMENT...`, exit 1 or 2.
  static void expect_one_error(const CommandResult& r, const std::string& subject, const std::string& fragment) {
    EXPECT_TRUE(r.status == 1 || r.status == 2) << r.status << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("seqtopo: error: " + subject + ": ", 0), 0U) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  std::string similarity() const {
    seqtopo::DenseMatrix<float> s(40, 40, 0.0F);
    for (std::size_t i = 0; i < 40; ++i) s(i, i) = 1.0F;
    seqtopo::io::write_npy(dir_.path / "s.npy", s);
    return (dir_.path / "s.npy").string();
  }
  std::string fifo(const std::string& name) const {
    const fs::path p = dir_.path / name;
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
    return p.string();
  }
  std::string out() const { return " --out " + (dir_.path / "out").string(); }
  const seqtopo::test_support::TempDir dir_;
};

TEST_F(SpecialFiles, DevZeroAsAnInputFileIsRefused) {
  const std::string s = similarity();
  expect_one_error(run("map " + s + " --odometry /dev/zero" + out()), "/dev/zero", "a character device");
  expect_one_error(run("map " + s + " --config /dev/zero" + out()), "/dev/zero", "a character device");
  expect_one_error(run("align --a /dev/zero"), "/dev/zero", "a character device");
  std::ofstream(dir_.path / "q.tsv") << "q0\tABCD\n";
  expect_one_error(run("match-strings --db /dev/zero --queries " + (dir_.path / "q.tsv").string() + out()), "/dev/zero",
                   "a character device");
  expect_one_error(run("fingerprint /dev/zero"), "/dev/zero", "a character device, not an image");
  // Not "no such video file": it is there, it is not a video.
  expect_one_error(run("map /dev/zero" + out()), "/dev/zero", "a character device, not an input file");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
}

TEST_F(SpecialFiles, DevZeroOnTheOnlineStdinIsRefused) {
  expect_one_error(run("map - --online --no-offline-outputs" + out(), "< /dev/zero"), "stdin", "NUL byte");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
  // A line of paths too long to be one path.
  std::ofstream(dir_.path / "long.txt") << std::string(100000, 'a') << "\n";
  expect_one_error(run("map - --online --no-offline-outputs" + out(), "< " + (dir_.path / "long.txt").string()),
                   "stdin", "longer than 4096 bytes");
}

TEST_F(SpecialFiles, AFifoIsRefusedNotWaitedFor) {
  // Nothing ever writes to these FIFOs: opening one to read would wait forever.
  const std::string image = fifo("frame.png");
  std::ofstream(dir_.path / "paths.txt") << image << "\n";
  expect_one_error(run("map - --online --no-offline-outputs" + out(), "< " + (dir_.path / "paths.txt").string()), image,
                   "a FIFO, not an image");
  const std::string npy = fifo("descriptors.npy");
  expect_one_error(run("map " + npy + out()), npy, "a FIFO");
  const std::string config = fifo("seqtopo.cfg");
  expect_one_error(run("map " + similarity() + " --config " + config + out()), config, "a FIFO");
  const std::string odometry = fifo("odometry.csv");
  expect_one_error(run("map " + similarity() + " --odometry " + odometry + out()), odometry, "a FIFO");
  EXPECT_FALSE(fs::exists(dir_.path / "out"));
}

}  // namespace
