// seqtopo-mpi under mpirun: 1 and 2 ranks write byte-identical alignments.json, equal to the sparse mode
// computed here in one process with the library, and a bad input fails on every rank with one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/formats/alignment_json.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_candidates.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/scale/synthetic_route.hpp"

namespace seqtopo {
namespace {

namespace fs = std::filesystem;

using test_support::CommandResult;
using test_support::read_file;

// `seqtopo-mpi ARGS` under mpirun with `ranks` ranks (run_command: no terminal input, stdout and stderr
// captured): offline and as root if need be (CI), shared memory and self transports only, no binding
// (ctest runs tests side by side), and Open MPI's session folder in the test's own folder (two runs starting
// at once race to create a shared one under /tmp).
CommandResult mpirun(const fs::path& dir, int ranks, const std::string& args) {
  return test_support::run_command(
      "exec env TMPDIR=" + dir.string() +
      " OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 " +
      std::string(SEQTOPO_MPIEXEC) + " -np " + std::to_string(ranks) +
      " --oversubscribe --bind-to none --mca btl self,vader --mca pml ob1 -q " + SEQTOPO_MPI_CLI + " " + args);
}

TEST(SeqtopoMpi, TwoRanksWriteTheAlignmentsOfOneProcess) {
  test_support::TempDir dir;
  const std::size_t n = 4000, dim = 64;
  auto route = scale::synthetic_route(n, dim, 7);
  const fs::path descriptors = dir.path / "descriptors.npy";
  io::write_npy(descriptors, DenseMatrix<float>(n, dim, std::move(route.descriptors)));

  const std::string input = "sparse " + descriptors.string() + " --out ";
  const CommandResult one = mpirun(dir.path, 1, input + (dir.path / "one.json").string());
  ASSERT_EQ(one.status, 0) << one.err;
  const CommandResult two = mpirun(dir.path, 2, input + (dir.path / "two.json").string());
  ASSERT_EQ(two.status, 0) << two.err;
  const std::string one_json = read_file(dir.path / "one.json"), two_json = read_file(dir.path / "two.json");
  EXPECT_EQ(one_json, two_json);

  // The same input in this process, with the library and seqtopo-mpi's defaults (MapConfig, k = 10,
  // background -1).
  const auto read = io::read_npy_matrix<float>(descriptors);
  const mapping::MapConfig map;
  scale::StreamingConfig streaming;
  streaming.contrast_window = map.score.contrast_window;
  streaming.contrast_offset = map.score.contrast_offset;
  const scale::StreamingSimilarity similarity(read.values, read.rows, read.cols, streaming);
  scale::CandidateConfig candidates;
  candidates.neighbours = 10;
  candidates.exclude = map.search.min_separation;
  const auto scores = scale::sparse_map_scores(similarity, -1.0F, candidates);
  const auto expected = scale::sparse_local_alignments_both(scores, mapping::align_config(map), 2);
  EXPECT_EQ(two_json, formats::alignments_to_json(expected).dump(1) + "\n");
  EXPECT_GE(expected.size(), 4U);  // the planted revisits, forward and backward
  bool reverse = false;
  for (const auto& a : expected) reverse = reverse || a.direction == align::Direction::reverse;
  EXPECT_TRUE(reverse);

  // Both ranks aligned something: "components per rank A,B".
  std::smatch m;
  ASSERT_TRUE(std::regex_search(two.err, m, std::regex("components per rank ([0-9]+),([0-9]+);"))) << two.err;
  EXPECT_GE(std::stoul(m[1]), 1U);
  EXPECT_GE(std::stoul(m[2]), 1U);
  EXPECT_NE(one.err.find("ranks 1,"), std::string::npos) << one.err;
}

TEST(SeqtopoMpi, BadInputFailsOnEveryRankWithOneLine) {
  test_support::TempDir dir;
  const fs::path bad = dir.path / "bad.npy";
  std::ofstream(bad) << "not a numpy file";
  const fs::path out = dir.path / "alignments.json";
  const CommandResult run = mpirun(dir.path, 2, "sparse " + bad.string() + " --out " + out.string());
  EXPECT_NE(run.status, 0);
  EXPECT_FALSE(fs::exists(out));
  // The tool's one line, from rank 0 only, naming the file.
  std::istringstream lines(run.err);
  std::string line;
  std::vector<std::string> ours;
  while (std::getline(lines, line)) {
    if (line.rfind("seqtopo-mpi:", 0) == 0) ours.push_back(line);
  }
  ASSERT_EQ(ours.size(), 1U) << run.err;
  EXPECT_EQ(ours[0].rfind("seqtopo-mpi: error: " + bad.string() + ": ", 0), 0U) << run.err;

  const CommandResult missing =
      mpirun(dir.path, 2, "sparse " + (dir.path / "missing.npy").string() + " --out " + out.string());
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.err.find("seqtopo-mpi: error: "), std::string::npos) << missing.err;

  // A bad command line is refused before MPI starts, still by the rank mpirun launched as 0 alone.
  const CommandResult option = mpirun(dir.path, 2, "sparse " + bad.string() + " --neighbours 0 --out " + out.string());
  EXPECT_NE(option.status, 0) << option.err;
  std::istringstream option_lines(option.err);
  std::vector<std::string> said;
  while (std::getline(option_lines, line)) {
    if (line.rfind("seqtopo-mpi:", 0) == 0) said.push_back(line);
  }
  ASSERT_EQ(said.size(), 1U) << option.err;
  EXPECT_EQ(said[0].rfind("seqtopo-mpi: error: --neighbours", 0), 0U) << option.err;
}

}  // namespace
}  // namespace seqtopo
