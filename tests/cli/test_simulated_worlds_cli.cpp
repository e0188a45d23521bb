// The simulator feeding the other commands, as a user chains them: the localization paper's rooms
// test (simulate -> fingerprint -> match-strings) and a mapping run with odometry on a figure-eight.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"

namespace {
namespace fs = std::filesystem;

using seqtopo::test_support::run_cli;

std::size_t data_lines(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) n += !line.empty() && line[0] != '#';
  return n;
}

TEST(SimulatedWorlds, RoomsThroughFingerprintsAndStringMatching) {
  seqtopo::test_support::TempDir dir;
  const std::string world = (dir.path / "rooms").string();
  const auto simulated = run_cli("simulate --scenario rooms --no-images --out " + world);
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  const auto map_points = run_cli("fingerprint " + world + "/panoramas --positions " + world +
                                  "/points.csv --role map --out " + world + "/map.tsv");
  ASSERT_EQ(map_points.status, 0) << map_points.err;
  const auto test_points = run_cli("fingerprint " + world + "/panoramas --positions " + world +
                                   "/points.csv --role test --out " + world + "/test.tsv");
  ASSERT_EQ(test_points.status, 0) << test_points.err;
  EXPECT_EQ(data_lines(world + "/map.tsv"), 10U);   // ten rooms, one map point each
  EXPECT_EQ(data_lines(world + "/test.tsv"), 30U);  // three test points per room
  for (const char* algorithm : {"A", "B", "C"}) {
    const std::string out = world + "/out-" + algorithm;
    const auto matched =
        run_cli("match-strings --db " + world + "/map.tsv --queries " + world + "/test.tsv --algorithm " + algorithm +
                " --adjacency " + world + "/adjacency.csv --out " + out);
    ASSERT_EQ(matched.status, 0) << algorithm << "\n" << matched.err;
    std::ifstream in(out + "/metrics.json");
    const auto metrics = nlohmann::json::parse(in);
    EXPECT_EQ(metrics.at("queries").get<int>(), 30);
    // The paper reports 90-97 % topologically correct on its rooms; separate rooms must be easy.
    EXPECT_GE(metrics.at("topological").at("correct_percent").get<double>(), 80.0) << algorithm;
    EXPECT_GE(data_lines(out + "/matches.tsv"), 30U);
  }
}

TEST(SimulatedWorlds, FigureEightMapsWithOdometry) {
  seqtopo::test_support::TempDir dir;
  const std::string world = (dir.path / "eight").string();
  const auto simulated = run_cli(
      "simulate --scenario figure-eight --no-images --interval 0.5 --panorama-width 120 --panorama-height 24 "
      "--supersample 1 --out " +
      world);
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  const std::size_t frames = data_lines(world + "/odometry.csv") - 1;  // minus the header
  ASSERT_GT(frames, 80U);
  EXPECT_EQ(data_lines(world + "/poses.csv") - 1, frames);
  EXPECT_EQ(data_lines(world + "/places.csv") - 1, frames);
  std::size_t panoramas = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(world + "/panoramas")) ++panoramas;
  EXPECT_EQ(panoramas, frames);

  const std::string out = (dir.path / "map").string();
  const auto mapped =
      run_cli("map " + world + "/panoramas --odometry " + world + "/odometry.csv --ground-truth " + world +
              "/ground_truth.png --gt-places " + world + "/places.csv --gt-poses " + world + "/poses.csv --out " + out);
  ASSERT_EQ(mapped.status, 0) << mapped.err;
  EXPECT_TRUE(fs::exists(out + "/metric_map.png"));
  std::ifstream in(out + "/metrics.json");
  const auto metrics = nlohmann::json::parse(in);
  for (const char* key : {"ate_odometry", "ate_ekf", "ate_pose_graph"})
    EXPECT_GE(metrics.at("metric").at(key).get<double>(), 0.0);
  EXPECT_EQ(metrics.at("topology").at("junctions_true").get<int>(), 2);  // the figure-eight's merge and branch
}

// Experiment 1 of the mapping paper: the corridor walked back in the opposite direction. Panoramas taken
// facing the other way are found by the heading-invariant panorama descriptor; the map's places match the
// true ones and the pose graph undoes most of the odometry's drift.
TEST(SimulatedWorlds, CorridorWalkedBackIsFoundWithThePanoramaDescriptor) {
  seqtopo::test_support::TempDir dir;
  const std::string world = (dir.path / "corridor").string();
  const auto simulated = run_cli(
      "simulate --scenario corridor-reverse --no-images --interval 0.5 --panorama-width 120 "
      "--panorama-height 24 --supersample 1 --out " +
      world);
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  const std::string out = (dir.path / "map").string();
  const auto mapped =
      run_cli("map " + world + "/panoramas --descriptor joint-histogram,panorama --min-separation 10 --odometry " +
              world + "/odometry.csv --ground-truth " + world + "/ground_truth.png --gt-places " + world +
              "/places.csv --gt-poses " + world + "/poses.csv --out " + out);
  ASSERT_EQ(mapped.status, 0) << mapped.err;
  std::ifstream in(out + "/metrics.json");
  const auto metrics = nlohmann::json::parse(in);
  EXPECT_GE(metrics.at("loop_closure").at("f1").get<double>(), 0.9);
  EXPECT_GE(metrics.at("topology").at("adjusted_rand_index").get<double>(), 0.9);
  EXPECT_LT(metrics.at("metric").at("ate_pose_graph").get<double>(),
            0.5 * metrics.at("metric").at("ate_odometry").get<double>());
  // The revisit is a reverse alignment.
  std::ifstream alignments_file(out + "/alignments.json");
  const auto alignments = nlohmann::json::parse(alignments_file);
  bool reverse_kept = false;
  for (const auto& a : alignments.at("alignments")) {
    reverse_kept = reverse_kept || (a.at("kept").get<bool>() && a.at("direction") == "reverse");
  }
  EXPECT_TRUE(reverse_kept);

  // With no descriptor option the 120 x 24 panoramas are recognised and get the same descriptors: the same map.
  // Asked for explicitly, the patch thumbnail is used as told.
  const std::string truth = " --min-separation 10 --odometry " + world + "/odometry.csv --ground-truth " + world +
                            "/ground_truth.png --gt-places " + world + "/places.csv";
  const auto automatic = run_cli("map " + world + "/panoramas" + truth + " --out " + out + "-auto");
  ASSERT_EQ(automatic.status, 0) << automatic.err;
  EXPECT_NE(automatic.err.find("120 x 24 images look like 360-degree panoramas"), std::string::npos) << automatic.err;
  EXPECT_EQ(seqtopo::test_support::read_file(out + "-auto/map.json"),
            seqtopo::test_support::read_file(out + "/map.json"));
  const auto patch =
      run_cli("map " + world + "/panoramas --descriptor joint-histogram,patch" + truth + " --out " + out + "-patch");
  ASSERT_EQ(patch.status, 0) << patch.err;
  EXPECT_EQ(patch.err.find("360-degree panoramas"), std::string::npos) << patch.err;
  EXPECT_NE(seqtopo::test_support::read_file(out + "-patch/map.json"),
            seqtopo::test_support::read_file(out + "/map.json"));
}

}  // namespace
