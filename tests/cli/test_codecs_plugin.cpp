// OpenCV's image and video codecs are a plugin opened on first use (seqtopo/image/codecs.hpp): the program
// itself needs none of their libraries, decodes and encodes through the plugin, and says in one line when the
// plugin cannot be loaded, leaving no output behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_command;

const fs::path kProgram = fs::path(SEQTOPO_CLI).parent_path() / "seqtopo-main";
const fs::path kCorridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";

CommandResult map_with_codecs(const std::string& codecs, const fs::path& out) {
  return run_command("exec env SEQTOPO_CODECS=" + codecs + " " + std::string(SEQTOPO_CLI) + " map " +
                     kCorridor.string() + " --ground-truth " + (kCorridor / "ground_truth.bmp").string() + " --out " +
                     out.string());
}

std::string last_line(std::string text) {
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text.substr(text.rfind('\n') + 1);
}

TEST(CodecsPlugin, TheProgramLinksNoCodecLibraryAndThePluginDoes) {
  const CommandResult program = run_command("ldd " + kProgram.string());
  ASSERT_EQ(program.status, 0) << program.err;
  EXPECT_NE(program.out.find("libopencv_core"), std::string::npos) << program.out;
  for (const std::string codec : {"libopencv_imgcodecs", "libopencv_videoio", "libgdal", "libavcodec"}) {
    EXPECT_EQ(program.out.find(codec), std::string::npos) << codec << " is loaded at every start:\n" << program.out;
  }
  const CommandResult plugin = run_command("ldd " + (kProgram.parent_path() / "libseqtopo_codecs.so").string());
  ASSERT_EQ(plugin.status, 0) << plugin.err;
  EXPECT_NE(plugin.out.find("libopencv_imgcodecs"), std::string::npos) << plugin.out;
  EXPECT_NE(plugin.out.find("libopencv_videoio"), std::string::npos) << plugin.out;
}

TEST(CodecsPlugin, APluginThatCannotBeLoadedIsOneLineAndNoOutput) {
  const seqtopo::test_support::TempDir dir;
  // No such file, and a shared library that is not the plugin.
  for (const std::string& codecs : {(dir.path / "none.so").string(), std::string("libz.so.1")}) {
    SCOPED_TRACE(codecs);
    const CommandResult r = map_with_codecs(codecs, dir.path / "out");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.status, -1) << "crashed";
    // The progress lines, then one error line naming the plugin and how to point at it.
    const std::string last = last_line(r.err);
    EXPECT_EQ(last.rfind("seqtopo: error: ", 0), 0U) << r.err;
    EXPECT_NE(last.find("libseqtopo_codecs.so"), std::string::npos) << r.err;
    EXPECT_NE(last.find("SEQTOPO_CODECS"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("error"), r.err.find(last) + std::string("seqtopo: ").size()) << "one error line: " << r.err;
    EXPECT_FALSE(fs::exists(dir.path / "out"));
  }
}

TEST(CodecsPlugin, ThePluginSeqtopoCodecsNamesIsUsed) {
  const seqtopo::test_support::TempDir dir;
  const CommandResult r = map_with_codecs((kProgram.parent_path() / "libseqtopo_codecs.so").string(), dir.path / "out");
  ASSERT_EQ(r.status, 0) << r.err;
  // Images decoded (the corridor's revisit found) and figures encoded through it.
  EXPECT_NE((r.out + r.err).find("F1 1.000"), std::string::npos) << r.out << r.err;
  EXPECT_GT(fs::file_size(dir.path / "out" / "similarity.png"), 100U);
}

}  // namespace
