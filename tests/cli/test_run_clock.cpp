// The run's clock starts at the launcher's main, not at the process's start: a script that builds seqtopo and then
// execs it (scripts/run.sh) started the process long before, and that time is not seqtopo's start-up.
#include <gtest/gtest.h>
#include <time.h>

#include <filesystem>
#include <regex>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"

namespace {
namespace fs = std::filesystem;

const fs::path kCorridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";

// The seconds of "wrote N files to DIR in S s" on stderr (-1 when absent).
double wrote_in(const std::string& err) {
  std::smatch m;
  static const std::regex line(R"(wrote \d+ files to \S+ in ([\d.]+) s)");
  return std::regex_search(err, m, line) ? std::stod(m[1].str()) : -1;
}

TEST(RunClock, StartsWhereTheLauncherHandsItOver) {
  const seqtopo::test_support::TempDir dir;
  timespec now{};
  clock_gettime(CLOCK_BOOTTIME, &now);
  const unsigned long long hour_ago = (static_cast<unsigned long long>(now.tv_sec) - 3600ULL) * 1000000000ULL;
  const std::string main_program = (fs::path(SEQTOPO_CLI).parent_path() / "seqtopo-main").string();
  // The program started by a launcher that began an hour ago counts that hour ...
  const auto handed = seqtopo::test_support::run_command("exec env SEQTOPO_STARTED_NS=" + std::to_string(hour_ago) +
                                                         " " + main_program + " map " + kCorridor.string() + " --out " +
                                                         (dir.path / "a").string());
  ASSERT_EQ(handed.status, 0) << handed.err;
  EXPECT_GE(wrote_in(handed.err), 3600.0) << handed.err;
  // ... and the launcher hands over its own start, whatever the environment said before.
  const auto launched =
      seqtopo::test_support::run_command("exec env SEQTOPO_STARTED_NS=" + std::to_string(hour_ago) + " " + SEQTOPO_CLI +
                                         " map " + kCorridor.string() + " --out " + (dir.path / "b").string());
  ASSERT_EQ(launched.status, 0) << launched.err;
  EXPECT_GE(wrote_in(launched.err), 0.0) << launched.err;
  EXPECT_LT(wrote_in(launched.err), 3600.0) << launched.err;
}

}  // namespace
