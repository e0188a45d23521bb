// seqtopo map --online from the outside: image paths fed one at a time on stdin while events.jsonl is read
// (every event of frame k is there before frame k + 1 is given, and none of a later frame), the same bytes as a
// run fed all at once, and bad input refused with one line.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/cli_run.hpp"
#include "common/corridor_laps.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/plot/png.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_cli;

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) out.push_back(line);
  return out;
}

// 1.jpg .. 84.jpg in numeric order, as the folder listing gives them.
std::vector<fs::path> corridor() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor")) {
    if (e.path().extension() == ".jpg") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return std::stoi(a.stem()) < std::stoi(b.stem()); });
  return files;
}

std::string path_lines(const std::vector<fs::path>& files) {
  std::string s;
  for (const auto& f : files) s += f.string() + "\n";
  return s;
}

void expect_clean_error(const CommandResult& o, const std::string& subject) {
  EXPECT_NE(o.status, 0);
  EXPECT_NE(o.status, -1) << "must exit, not crash";
  EXPECT_EQ(o.err.rfind("seqtopo: error: " + subject, 0), 0U) << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "one line: " << o.err;
}

// An error found once frames are in: the line saying where events.jsonl is written comes first.
void expect_error_after_frames(const CommandResult& o, const std::string& subject) {
  EXPECT_NE(o.status, 0);
  EXPECT_NE(o.status, -1) << "must exit, not crash";
  const auto lines = lines_of(o.err);
  ASSERT_EQ(lines.size(), 2U) << o.err;
  EXPECT_EQ(lines[0].rfind("seqtopo map: events.jsonl is written to ", 0), 0U) << o.err;
  EXPECT_EQ(lines[1].rfind("seqtopo: error: " + subject, 0), 0U) << o.err;
}

TEST(MapOnline, EventsOfFrameKAreReadableBeforeFrameKPlusOneIsGiven) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("one online run per frame of the corridor");
  const seqtopo::test_support::TempDir dir;
  const auto files = corridor();
  ASSERT_EQ(files.size(), 84U);
  // The reference: every path at once.
  const auto all =
      run_cli("map - --online --no-offline-outputs --out " + (dir.path / "all").string(), path_lines(files));
  ASSERT_EQ(all.status, 0) << all.err;
  const std::string reference = read_text(dir.path / "all" / "events.jsonl");
  std::vector<std::size_t> frame_of;
  for (const auto& line : lines_of(reference)) frame_of.push_back(nlohmann::json::parse(line)["frame"]);
  ASSERT_TRUE(std::is_sorted(frame_of.begin(), frame_of.end())) << "events in frame order";
  ASSERT_GT(frame_of.size(), 20U) << "the corridor's revisit gives events";
  EXPECT_EQ(std::count(all.out.begin(), all.out.end(), '\n'), static_cast<long>(frame_of.size()))
      << "one stdout line per event";

  // The same frames one at a time through a pipe.
  int in[2];
  ASSERT_EQ(::pipe(in), 0);
  const fs::path err_file = dir.path / "stderr.txt";
  const std::string out_dir = (dir.path / "live").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(in[0], 0);
    ::close(in[1]);
    const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(err, 2);
    ::dup2(null, 1);
    ::execl(SEQTOPO_CLI, SEQTOPO_CLI, "map", "-", "--online", "--no-offline-outputs", "--out", out_dir.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(in[0]);
  const auto deadline = [] { return std::chrono::steady_clock::now() + std::chrono::seconds(60); };
  // The live file's path, announced on stderr once the first frame is in.
  const std::string first = files[0].string() + "\n";
  ASSERT_EQ(::write(in[1], first.data(), first.size()), static_cast<ssize_t>(first.size()));
  fs::path live;
  for (auto until = deadline(); live.empty() && std::chrono::steady_clock::now() < until;) {
    const std::string text = read_text(err_file);
    const std::string key = "events.jsonl is written to ";
    if (const auto at = text.find(key); at != std::string::npos) {
      const auto end = text.find(" as the frames", at);
      if (end != std::string::npos) live = text.substr(at + key.size(), end - at - key.size());
    }
    if (live.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_FALSE(live.empty()) << read_text(err_file);
  const auto ref_lines = lines_of(reference);
  for (std::size_t k = 0; k + 1 < files.size(); ++k) {
    const std::string line = files[k].string() + "\n";
    if (k > 0) {
      ASSERT_EQ(::write(in[1], line.data(), line.size()), static_cast<ssize_t>(line.size()));
    }
    // Every event of frames <= k, and nothing else, once frame k is consumed.
    const auto expected =
        static_cast<std::size_t>(std::upper_bound(frame_of.begin(), frame_of.end(), k) - frame_of.begin());
    std::string want;
    for (std::size_t e = 0; e < expected; ++e) want += ref_lines[e] + "\n";
    std::string got;
    for (auto until = deadline(); std::chrono::steady_clock::now() < until;) {
      got = read_text(live);
      if (got.size() >= want.size()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_EQ(got, want) << "after frame " << k;
  }
  const std::string last = files.back().string() + "\n";
  ASSERT_EQ(::write(in[1], last.data(), last.size()), static_cast<ssize_t>(last.size()));
  ::close(in[1]);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_text(err_file);
  EXPECT_EQ(read_text(dir.path / "live" / "events.jsonl"), reference) << "the same bytes fed at once or one by one";
}

TEST(MapOnline, WritesTheOnlineAndTheOfflineOutputs) {
  const seqtopo::test_support::TempDir dir;
  const fs::path data = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  const auto o = run_cli("map " + data.string() + " --online --ground-truth " + (data / "ground_truth.bmp").string() +
                         " --out " + (dir.path / "out").string());
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* name : {"events.jsonl", "online_loop_closures.csv", "online.json", "map.json", "report.html"}) {
    EXPECT_TRUE(fs::exists(dir.path / "out" / name)) << name;
  }
  const auto summary = nlohmann::json::parse(read_text(dir.path / "out" / "online.json"));
  EXPECT_GT(summary["metrics"]["f1"].get<double>(), 0.5);
  EXPECT_TRUE(summary.contains("offline_metrics"));
  // 84 frames leave too few chance islands for a fit: the statistics are the offline fit of the table so far,
  // and the threshold their score of E = 0.01, below the fallback of 20.
  const auto& significance = summary["significance"];
  EXPECT_EQ(significance["max_e_value"].get<double>(), 0.01);
  EXPECT_EQ(significance["fitted_to"], "table");
  EXPECT_GT(significance["lambda"].get<double>(), 0.0);
  EXPECT_LT(significance["threshold"].get<double>(), 20.0);
  EXPECT_GT(significance["threshold"].get<double>(), 3.0);
  // Its scores are in the logarithmic phase: the offset stays.
  EXPECT_EQ(summary["significance"]["contrast_offset"].get<double>(), 0.5);
  EXPECT_TRUE(summary["significance"]["offset_changes"].empty());
  std::ifstream events(dir.path / "out" / "events.jsonl");
  std::string line;
  std::size_t closures = 0;
  while (std::getline(events, line)) {
    const auto e = nlohmann::json::parse(line);
    if (e["event"] != "loop_closure") continue;
    ++closures;
    // Each at its revisit's E-value in the frames so far: significant, as the threshold demands.
    ASSERT_TRUE(e.contains("e_value") && e["e_value"].is_number()) << line;
    EXPECT_LE(e["e_value"].get<double>(), 0.01) << line;
  }
  EXPECT_GT(closures, 0U);
  EXPECT_NE(o.err.find("chance alignments of the table so far"), std::string::npos) << o.err;
}

// Image paths on stdin: the offline map is made of the files they name, in their order (no folder of links), so it
// is the folder's map when the paths list the folder in its order, and errors name the user's files.
TEST(MapOnline, StdinPathsGetTheOfflineMapOfTheFilesTheyName) {
  const seqtopo::test_support::TempDir dir;
  const fs::path data = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  std::ofstream(dir.path / "paths.txt") << path_lines(corridor());
  const std::string truth = " --ground-truth " + (data / "ground_truth.bmp").string();
  const auto piped = run_cli("map - --online" + truth + " --out " + (dir.path / "piped").string() + " < " +
                             (dir.path / "paths.txt").string());
  ASSERT_EQ(piped.status, 0) << piped.err;
  const auto folder = run_cli("map " + data.string() + truth + " --out " + (dir.path / "folder").string());
  ASSERT_EQ(folder.status, 0) << folder.err;
  EXPECT_EQ(read_text(dir.path / "piped" / "loop_closures.csv"), read_text(dir.path / "folder" / "loop_closures.csv"));
  EXPECT_TRUE(fs::exists(dir.path / "piped" / "report.html"));
  const auto summary = nlohmann::json::parse(read_text(dir.path / "piped" / "online.json"));
  const auto offline = nlohmann::json::parse(read_text(dir.path / "folder" / "metrics.json"));
  EXPECT_EQ(summary["offline_metrics"]["f1"], offline["loop_closure"]["f1"]);
}

// White-noise descriptors, and their cosine similarity as a similarity.npy: the offset is raised where the scores'
// chance paths would grow with the run (one stderr line, online.json), and no chance loop closure stands.
TEST(MapOnline, WhiteNoiseRaisesTheOffsetAndGivesNoLoopClosure) {
  const seqtopo::test_support::TempDir dir;
  const std::size_t n = 300, dim = 128;
  std::mt19937 rng(11);
  std::normal_distribution<float> normal;
  seqtopo::DenseMatrix<float> x(n, dim);
  for (auto& v : x.values) v = normal(rng);
  seqtopo::DenseMatrix<float> s(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      double dot = 0, a = 0, b = 0;
      for (std::size_t k = 0; k < dim; ++k) dot += x(i, k) * x(j, k), a += x(i, k) * x(i, k), b += x(j, k) * x(j, k);
      s(i, j) = static_cast<float>(dot / std::sqrt(a * b));
    }
  }
  seqtopo::io::write_npy(dir.path / "descriptors.npy", x);
  seqtopo::io::write_npy(dir.path / "similarity.npy", s);
  for (const char* input : {"descriptors.npy", "similarity.npy"}) {
    const fs::path out = dir.path / (std::string("out_") + input);
    const auto o =
        run_cli("map " + (dir.path / input).string() + " --online --no-offline-outputs --out " + out.string());
    ASSERT_EQ(o.status, 0) << o.err;
    EXPECT_NE(o.err.find("online contrast offset 0.50: the scores' global alignment rate"), std::string::npos) << o.err;
    const auto summary = nlohmann::json::parse(read_text(out / "online.json"));
    EXPECT_GT(summary["significance"]["contrast_offset"].get<double>(), 0.5) << input;
    ASSERT_FALSE(summary["significance"]["offset_changes"].empty()) << input;
    EXPECT_EQ(summary["significance"]["offset_changes"][0]["check"], "scores") << input;
    EXPECT_EQ(lines_of(read_text(out / "online_loop_closures.csv")).size(), 1U) << input << ": only the header";
  }
}

// The online map counts frames unless it is given a scale: with --frames-per-place F its windows and separations are
// places, as the offline map's (5 places of 2 frames are the 10 frames of the frame run); auto is refused.
TEST(MapOnline, FramesPerPlaceMakesTheWindowsPlaces) {
  const seqtopo::test_support::TempDir dir;
  const fs::path data = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  const std::string base = "map " + data.string() + " --online --no-offline-outputs --out ";
  const auto places =
      run_cli(base + (dir.path / "places").string() + " --frames-per-place 2 --min-separation 5 --contrast-window 6");
  ASSERT_EQ(places.status, 0) << places.err;
  const auto frames = run_cli(base + (dir.path / "frames").string() + " --min-separation 10 --contrast-window 12");
  ASSERT_EQ(frames.status, 0) << frames.err;
  const std::string closures = read_text(dir.path / "places" / "online_loop_closures.csv");
  EXPECT_GT(lines_of(closures).size(), 10U);
  EXPECT_EQ(closures, read_text(dir.path / "frames" / "online_loop_closures.csv"));
  EXPECT_EQ(read_text(dir.path / "places" / "events.jsonl"), read_text(dir.path / "frames" / "events.jsonl"));
  const auto automatic = run_cli(base + (dir.path / "auto").string() + " --frames-per-place auto");
  EXPECT_NE(automatic.status, 0);
  EXPECT_NE(automatic.err.find("--frames-per-place auto"), std::string::npos) << automatic.err;
}

// Several inputs are the sessions of one map: the corridor's two laps given as two folders are its frames in one
// folder, online and offline (byte for byte online), and both summaries list the sessions.
TEST(MapOnline, SeveralInputsAreTheSessionsOfOneMap) {
  const seqtopo::test_support::TempDir dir;
  seqtopo::test_support::corridor_laps(dir.path);
  const fs::path data = seqtopo::test_support::corridor_folder();
  const std::string truth = " --ground-truth " + (data / "ground_truth.bmp").string();
  const auto two = run_cli("map " + (dir.path / "lap1").string() + " " + (dir.path / "lap2").string() + " --online" +
                           truth + " --out " + (dir.path / "two").string());
  ASSERT_EQ(two.status, 0) << two.err;
  const auto one = run_cli("map " + data.string() + " --online" + truth + " --out " + (dir.path / "one").string());
  ASSERT_EQ(one.status, 0) << one.err;
  for (const char* name : {"online_loop_closures.csv", "events.jsonl", "loop_closures.csv"}) {
    EXPECT_EQ(read_text(dir.path / "two" / name), read_text(dir.path / "one" / name)) << name;
  }
  const auto summary = nlohmann::json::parse(read_text(dir.path / "two" / "online.json"));
  ASSERT_EQ(summary["sessions"].size(), 2U);
  EXPECT_EQ(summary["sessions"][1]["begin"], 40);
  EXPECT_EQ(summary["sessions"][1]["end"], 84);
  EXPECT_EQ(summary["metrics"]["f1"], summary["offline_metrics"]["f1"]);
  const auto map = nlohmann::json::parse(read_text(dir.path / "two" / "map.json"));
  EXPECT_EQ(map["sessions"].size(), 2U);
  EXPECT_FALSE(nlohmann::json::parse(read_text(dir.path / "one" / "online.json")).contains("sessions"));
}

TEST(MapOnline, BadInputGivesOneLine) {
  const seqtopo::test_support::TempDir dir;
  const std::string out = " --out " + (dir.path / "out").string();
  expect_clean_error(run_cli("map a b --online" + out), "a");  // every session must exist
  expect_clean_error(run_cli("map a --online --e-value 0" + out), "--e-value");
  expect_clean_error(run_cli("map " + (dir.path / "missing").string() + " --online" + out),
                     (dir.path / "missing").string());
  const std::string missing_image = (dir.path / "nope.png").string();
  expect_clean_error(run_cli("map - --online" + out, missing_image + "\n"), missing_image);
  expect_clean_error(run_cli("map - --online" + out, "\n"), "stdin");
  expect_clean_error(run_cli("map - --online --threshold 100" + out, "x\n"), "--online");
  // One image is no sequence (the offline map named its own link folder); a folder is not an image.
  const auto images = corridor();
  expect_error_after_frames(run_cli("map - --online" + out, path_lines({images[0]})),
                            "stdin: needs at least 2 images, got 1");
  expect_error_after_frames(run_cli("map - --online" + out, path_lines({images[0], images[0].parent_path()})),
                            images[0].parent_path().string() + ": a folder, not an image");
  // An image of another size among the paths: the offline map's error names the user's file, not the link the
  // run made for it in a folder of its own.
  const fs::path small = dir.path / "small.png";
  seqtopo::plot::write_png(small, seqtopo::RgbImage(16, 12));
  const auto mixed = run_cli("map - --online" + out, path_lines({images[0], images[1], images[2], small}));
  EXPECT_NE(mixed.status, 0);
  EXPECT_NE(mixed.err.find(small.string()), std::string::npos) << mixed.err;
  EXPECT_EQ(mixed.err.find("seqtopo-online"), std::string::npos) << mixed.err;
  // Sessions are of one kind; image paths on stdin are one input alone.
  const std::string folder = images[0].parent_path().string();
  const fs::path rows = dir.path / "descriptors.npy";
  seqtopo::io::write_npy(rows, seqtopo::DenseMatrix<float>(5, 3, 1.0F));
  expect_clean_error(run_cli("map " + folder + " " + rows.string() + " --online" + out),
                     rows.string() + ": is descriptors, the first session images");
  expect_clean_error(run_cli("map - " + folder + " --online" + out, path_lines({images[0]})),
                     "-: image paths on stdin");
  // The offline map's options are refused, not ignored.
  const auto odometry = dir.path / "odometry.csv";
  std::ofstream(odometry) << "index,x,y,theta\n";
  const auto ignored = run_cli("map " + folder + " --online --odometry " + odometry.string() + " --preset paper" + out);
  expect_clean_error(ignored, "--online: does not take --odometry, --preset (the offline map's options");
  EXPECT_FALSE(fs::exists(dir.path / "out")) << "no output folder on error";
}

}  // namespace
