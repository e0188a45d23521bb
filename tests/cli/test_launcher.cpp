// The `seqtopo` launcher (src/launcher/main.cpp): it starts seqtopo-main beside it or in ../libexec/seqtopo/ with
// the same arguments, adding glibc.malloc.hugetlb=1 to GLIBC_TUNABLES for the commands that hold N x N matrices
// (not for --online, and never over a GLIBC_TUNABLES that already names it). Checked with a copy of the launcher
// and a stand-in program that prints what it was given.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_command;

class Launcher : public ::testing::Test {
 protected:
  // A copy of the launcher in `folder` (made), with the stand-in program at `program` (when not empty).
  fs::path install(const fs::path& folder, const fs::path& program) const {
    fs::create_directories(folder);
    fs::copy_file(SEQTOPO_CLI, folder / "seqtopo", fs::copy_options::overwrite_existing);
    if (!program.empty()) {
      fs::create_directories(program.parent_path());
      dir_.write(fs::relative(program, dir_.path).string(), "#!/bin/sh\necho \"$GLIBC_TUNABLES|$*\"\n");
      fs::permissions(program, fs::perms::owner_all);
    }
    return folder / "seqtopo";
  }
  // What the stand-in printed when started by `launcher ARGS` with GLIBC_TUNABLES = `tunables` (unset when empty).
  static std::string given(const fs::path& launcher, const std::string& args, const std::string& tunables = {}) {
    const std::string env = tunables.empty() ? "env -u GLIBC_TUNABLES " : "env GLIBC_TUNABLES=" + tunables + " ";
    const CommandResult r = run_command(env + launcher.string() + " " + args);
    EXPECT_EQ(r.status, 0) << r.err;
    return r.out;
  }
  const seqtopo::test_support::TempDir dir_;
};

// What the launcher adds to an unset GLIBC_TUNABLES for a matrix command (nothing under AddressSanitizer, whose
// allocator reads no glibc tunables).
#if defined(__SANITIZE_ADDRESS__)
const std::string kHuge;
#else
const std::string kHuge = "glibc.malloc.hugetlb=1";
#endif

TEST_F(Launcher, StartsTheProgramBesideItWithHugePagesForTheMatrixCommands) {
  const fs::path launcher = install(dir_.path / "bin", dir_.path / "bin" / "seqtopo-main");
  EXPECT_EQ(given(launcher, "map some/folder --out o"), kHuge + "|map some/folder --out o\n");
  EXPECT_EQ(given(launcher, "localize --map a --query b"), kHuge + "|localize --map a --query b\n");
  EXPECT_EQ(given(launcher, "similarity x"), kHuge + "|similarity x\n");
  EXPECT_EQ(given(launcher, "bench align"), kHuge + "|bench align\n");
  // Online frames should not wait for the kernel to compact memory; the other commands hold no N x N matrix.
  EXPECT_EQ(given(launcher, "map x --online"), "|map x --online\n");
  EXPECT_EQ(given(launcher, "align --help"), "|align --help\n");
  EXPECT_EQ(given(launcher, "--version"), "|--version\n");
  EXPECT_EQ(given(launcher, ""), "|\n");
  // The user's own tunables are kept; one that names hugetlb (=0 turns it off) is left as it is.
  EXPECT_EQ(given(launcher, "map x", "glibc.malloc.check=0"),
            (kHuge.empty() ? "glibc.malloc.check=0" : "glibc.malloc.check=0:" + kHuge) + "|map x\n");
  EXPECT_EQ(given(launcher, "map x", "glibc.malloc.hugetlb=0"), "glibc.malloc.hugetlb=0|map x\n");
}

TEST_F(Launcher, FindsTheInstalledProgramInLibexec) {
  const fs::path launcher =
      install(dir_.path / "prefix" / "bin", dir_.path / "prefix" / "libexec" / "seqtopo" / "seqtopo-main");
  EXPECT_EQ(given(launcher, "align x"), "|align x\n");
}

TEST_F(Launcher, AMissingProgramIsOneErrorLine) {
  const fs::path launcher = install(dir_.path / "alone", {});
  const CommandResult r = run_command(launcher.string() + " map");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "seqtopo: error: " + (dir_.path / "alone" / "seqtopo-main").string() +
                       ": the command-line program is missing (reinstall seqtopo)\n");
}

}  // namespace
