// Several sessions in one map, and a 30 fps recording thinned by distance travelled, as a user runs them:
//  * Nordland summer and winter given as two sessions: no edge joins one season's end to the other's start,
//    the loop-closure F1 is at least the single folder's, map.json records the sessions;
//  * the corridor re-recorded at 30 fps (variable speed, a stop) with times.txt and 50 Hz timestamped
//    odometry, mapped with --every-metres 0.5: the folder's F1 within 0.03;
//  * localize against a map of two sessions gives the answers of the same map as one folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>

#include "common/cli_run.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/image/grey_matrix_file.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/session_input.hpp"

namespace seqtopo {
namespace {

namespace fs = std::filesystem;
using test_support::read_file;
using test_support::run_cli;
using test_support::TempDir;

const fs::path kCorridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
const fs::path kNordland = fs::path(SEQTOPO_SHARED_DATA_DIR) / "nordland-64x32";

nlohmann::json json_of(const fs::path& p) { return nlohmann::json::parse(read_file(p)); }

double f1_of(const fs::path& out) { return json_of(out / "metrics.json").at("loop_closure").at("f1").get<double>(); }

// Whether map.json has an edge between the places of images a and b.
bool edge_between(const nlohmann::json& map, std::size_t a, std::size_t b) {
  const int p = map.at("labels")[a], q = map.at("labels")[b];
  for (const auto& e : map.at("edges")) {
    if ((e[0] == std::min(p, q) && e[1] == std::max(p, q))) return true;
  }
  return false;
}

TEST(Sessions, NordlandSummerAndWinterAsTwoSessions) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("3,600 Nordland frames");
  if (!fs::exists(kNordland / "summer")) GTEST_SKIP() << "no Nordland data at " << kNordland;
  TempDir dir;
  // The single-folder protocol of the README: summer then winter in one folder (links), poses.csv giving
  // frame k of either season the position (k, 0).
  const fs::path both = dir.path / "both";
  fs::create_directory(both);
  const auto summer = pipeline::list_images(kNordland / "summer");
  const auto winter = pipeline::list_images(kNordland / "winter");
  ASSERT_EQ(summer.size(), winter.size());
  const std::size_t n = summer.size();
  for (const auto& f : summer) fs::create_symlink(f, both / ("a-" + f.filename().string()));
  for (const auto& f : winter) fs::create_symlink(f, both / ("b-" + f.filename().string()));
  std::ofstream poses(dir.path / "poses.csv");
  poses << "index,x,y\n";
  for (std::size_t k = 0; k < 2 * n; ++k) poses << k << "," << k % n << ",0\n";
  poses.close();
  const std::string truth = " --ground-truth " + (dir.path / "poses.csv").string() + " --gt-radius 2";

  const auto single = run_cli("map " + both.string() + truth + " --out " + (dir.path / "single").string());
  ASSERT_EQ(single.status, 0) << single.err;
  const auto two = run_cli("map " + (kNordland / "summer").string() + " " + (kNordland / "winter").string() + truth +
                           " --out " + (dir.path / "two").string());
  ASSERT_EQ(two.status, 0) << two.err;

  const auto map1 = json_of(dir.path / "single" / "map.json"), map2 = json_of(dir.path / "two" / "map.json");
  // One folder invents a transition from summer's last frame to winter's first; two sessions do not.
  EXPECT_TRUE(edge_between(map1, n - 1, n)) << "the single folder was expected to join the seasons' ends";
  EXPECT_FALSE(edge_between(map2, n - 1, n)) << "an edge joins summer's end and winter's start";
  const double f1_single = f1_of(dir.path / "single"), f1_two = f1_of(dir.path / "two");
  EXPECT_GE(f1_two, f1_single);
  EXPECT_GE(f1_two, 0.95);
  ASSERT_EQ(map2.at("sessions").size(), 2U);
  EXPECT_EQ(map2.at("sessions")[0].at("begin"), 0);
  EXPECT_EQ(map2.at("sessions")[0].at("end"), n);
  EXPECT_EQ(map2.at("sessions")[1].at("begin"), n);
  EXPECT_EQ(map2.at("sessions")[1].at("end"), 2 * n);
  EXPECT_EQ(map2.at("image_sessions").size(), 2 * n);
  EXPECT_EQ(map2.at("image_sessions")[n - 1], 0);
  EXPECT_EQ(map2.at("image_sessions")[n], 1);
  EXPECT_FALSE(map1.contains("sessions"));  // a single input's map.json is as before
  // One path seen twice: as two sessions a path of about n places (no cycle, no junction, two dead ends), where
  // nearly every winter frame shares the place of its summer frame; as one folder, the same closed into one cycle
  // by the invented transition.
  for (const auto* map : {&map1, &map2}) {
    const std::size_t places = map->at("places").size(), edges = map->at("edges").size();
    std::vector<int> degree(places, 0);
    for (const auto& e : map->at("edges")) {
      ++degree[e[0].get<std::size_t>()];
      ++degree[e[1].get<std::size_t>()];
    }
    EXPECT_NEAR(static_cast<double>(places), static_cast<double>(n), 0.02 * static_cast<double>(n));
    EXPECT_EQ(edges, map == &map2 ? places - 1 : places);  // one component each (the labels' walk is connected)
    EXPECT_TRUE(map->at("junctions").empty()) << map->at("junctions").dump();
    EXPECT_EQ(std::count(degree.begin(), degree.end(), 1), map == &map2 ? 2 : 0);
    EXPECT_EQ(std::count_if(degree.begin(), degree.end(), [](int d) { return d >= 3; }), 0);
    std::size_t shared = 0;
    for (std::size_t k = 0; k < n; ++k) shared += map->at("labels")[k] == map->at("labels")[n + k] ? 1 : 0;
    EXPECT_GE(static_cast<double>(shared), 0.95 * static_cast<double>(n));
  }
  std::cerr << "Nordland: F1 single folder " << f1_single << ", two sessions " << f1_two << "\n";
}

// ---- the corridor at 30 fps --------------------------------------------------------------------------------

// The corridor's loop (40 images a lap on a 20 m circle), at image parameter u (image k at u = k).
Pose2 loop_pose(double u) {
  const double a = 2 * std::numbers::pi * u / 40.0, r = 20.0 / (2 * std::numbers::pi);
  return {r * std::sin(a), r * (1 - std::cos(a)), wrap_angle(a)};
}

TEST(EveryMetres, CorridorAt30FpsMapsAsTheFolder) {
  TempDir dir;
  const auto originals = pipeline::list_images(kCorridor);
  ASSERT_EQ(originals.size(), 84U);
  // The robot's progress u(t) [images] at 0.5 m per image: speed 0.6 +- 0.4 m/s over 20 s, standing still for
  // 3 s at t = 30 s; integrated finely, sampled at 30 fps (frames) and at 50 Hz (odometry). The recording goes
  // on a little past the last image (as a robot does), so that the last image is reached.
  const double t0 = 1000.0, step = 1.0 / 3000.0;
  std::vector<double> u_of{0.0};  // u at t0 + k * step
  for (double t = 0; u_of.back() < 83.4; t += step) {
    const double v = (t >= 30.0 && t < 33.0) ? 0.0 : 0.6 + 0.4 * std::sin(2 * std::numbers::pi * t / 20.0);
    u_of.push_back(u_of.back() + step * v / 0.5);
  }
  const double duration = static_cast<double>(u_of.size() - 1) * step;
  auto u_at = [&](double t) {
    return u_of[std::min(u_of.size() - 1, static_cast<std::size_t>(std::llround(t / step)))];
  };

  const fs::path frames = dir.path / "frames";
  fs::create_directory(frames);
  std::ofstream times(frames / "times.txt");
  times.precision(17);
  std::vector<std::size_t> original_of_frame;
  for (std::size_t f = 0; static_cast<double>(f) / 30.0 <= duration; ++f) {
    const double t = static_cast<double>(f) / 30.0;
    const auto k = static_cast<std::size_t>(std::llround(std::min(83.0, u_at(t))));
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05zu.jpg", f);
    fs::create_symlink(originals[k], frames / name);
    times << t0 + t << "\n";
    original_of_frame.push_back(k);
  }
  times.close();
  std::ofstream odometry(dir.path / "odometry.csv");
  odometry.precision(17);
  odometry << "timestamp,x,y,yaw\n";
  for (double t = 0; t <= duration; t += 0.02) {
    const Pose2 p = loop_pose(u_at(t));
    odometry << t0 + t << "," << p.x << "," << p.y << "," << p.theta << "\n";
  }
  odometry.close();
  ASSERT_GT(original_of_frame.size(), 2000U);  // a real 30 fps recording, not 84 images

  // The frames --every-metres keeps, by the library call the command makes, for the ground truth of the kept
  // frames: kept frames i, j are the same place when the corridor's truth says so of their originals.
  pipeline::SessionSource session;
  session.input = pipeline::SequenceInput(frames);
  session.odometry = dir.path / "odometry.csv";
  session.every_metres = 0.5;
  const pipeline::PreparedSession prepared = pipeline::prepare_session(session);
  const auto& kept = prepared.input.frames;
  ASSERT_GT(kept.size(), 80U);
  ASSERT_LT(kept.size(), 90U);
  const auto truth = image::read_grey_matrix_image(kCorridor / "ground_truth.bmp");
  std::ofstream pgm(dir.path / "truth.pgm", std::ios::binary);
  pgm << "P5\n" << kept.size() << " " << kept.size() << "\n255\n";
  for (std::size_t i : kept) {
    for (std::size_t j : kept) pgm.put(truth(original_of_frame[i], original_of_frame[j]) ? char(255) : char(0));
  }
  pgm.close();

  const auto folder = run_cli("map --out " + (dir.path / "folder").string());
  ASSERT_EQ(folder.status, 0) << folder.err;
  const auto thinned = run_cli("map " + frames.string() + " --odometry " + (dir.path / "odometry.csv").string() +
                               " --every-metres 0.5 --ground-truth " + (dir.path / "truth.pgm").string() + " --out " +
                               (dir.path / "thinned").string());
  ASSERT_EQ(thinned.status, 0) << thinned.err;
  EXPECT_NE(thinned.err.find("--every-metres 0.5: " + std::to_string(kept.size()) + " of " +
                             std::to_string(original_of_frame.size()) + " frames kept"),
            std::string::npos)
      << thinned.err;
  EXPECT_EQ(json_of(dir.path / "thinned" / "map.json").at("images"), kept.size());
  const double f1_folder = f1_of(dir.path / "folder"), f1_thinned = f1_of(dir.path / "thinned");
  EXPECT_NEAR(f1_thinned, f1_folder, 0.03);
  std::cerr << "corridor: " << original_of_frame.size() << " frames at 30 fps, " << kept.size() << " kept; F1 folder "
            << f1_folder << ", --every-metres 0.5 " << f1_thinned << "\n";

  // Without odometry, --every-metres is refused before any work.
  const auto refused = run_cli("map " + frames.string() + " --every-metres 0.5 --out " + (dir.path / "no").string());
  EXPECT_NE(refused.status, 0);
  EXPECT_EQ(refused.err_last_line().rfind("seqtopo: error: --every-metres: needs odometry", 0), 0U) << refused.err;
  EXPECT_FALSE(fs::exists(dir.path / "no"));
}

// ---- localize in a map of two sessions --------------------------------------------------------------------

TEST(Sessions, LocalizeInAMapOfTwoSessions) {
  TempDir dir;
  const auto files = pipeline::list_images(kCorridor);
  for (const char* name : {"first", "second", "whole"}) fs::create_directory(dir.path / name);
  for (std::size_t k = 0; k < files.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "%03zu.jpg", k);
    fs::create_symlink(files[k], dir.path / (k < 42 ? "first" : "second") / name);
    fs::create_symlink(files[k], dir.path / "whole" / name);
  }
  const auto two =
      run_cli("localize --map " + (dir.path / "first").string() + " --map " + (dir.path / "second").string() +
              " --query " + kCorridor.string() + " --out " + (dir.path / "two").string());
  ASSERT_EQ(two.status, 0) << two.err;
  const auto one = run_cli("localize --map " + (dir.path / "whole").string() + " --query " + kCorridor.string() +
                           " --out " + (dir.path / "one").string());
  ASSERT_EQ(one.status, 0) << one.err;
  EXPECT_EQ(read_file(dir.path / "two" / "matches.csv"), read_file(dir.path / "one" / "matches.csv"));
  EXPECT_NE(two.err.find("84 query frames in 84 map frames"), std::string::npos) << two.err;
}

TEST(Sessions, OdometryPerSessionOrNone) {
  TempDir dir;
  std::ofstream(dir.path / "odo.csv") << "index,x,y,theta\n0,0,0,0\n";
  const auto r = run_cli("map " + kCorridor.string() + " " + kCorridor.string() + " --odometry " +
                         (dir.path / "odo.csv").string() + " --out " + (dir.path / "out").string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err_last_line(),
            "seqtopo: error: --odometry: given once for 2 sessions: give it once per session, in the order of the "
            "inputs");
  EXPECT_FALSE(fs::exists(dir.path / "out"));
}

}  // namespace
}  // namespace seqtopo
