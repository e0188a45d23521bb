// A break inside one input is a session break (timeline/session_breaks.hpp), end to end: two recordings in one
// folder map as the two given as sessions; a cut inside a walk is found at its frame, offline and online (an event);
// a pause (a gap in time where the frames either side are neighbours) is one session; a continuous walk (the
// corridor, the simulator's worlds at several seeds) has no break.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/cli_run.hpp"
#include "common/corridor_laps.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"

namespace seqtopo {
namespace {

namespace fs = std::filesystem;
using test_support::read_file;
using test_support::run_cli;
using test_support::TempDir;

// The panoramas of a simulated world (names 00000.png, ...: times one second apart), made once per test.
std::vector<fs::path> world(const fs::path& dir, const std::string& scenario, int seed) {
  const fs::path out = dir / (scenario + std::to_string(seed));
  const auto r = run_cli("simulate --scenario " + scenario + " --seed " + std::to_string(seed) +
                         " --no-images --supersample 1 --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(out / "panoramas")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// A folder of links to `parts`' frames, each part's names numbered on from its first number: a gap between
// numbers is a gap in the frames' times.
fs::path folder(const fs::path& at, const std::vector<std::pair<long, std::vector<fs::path>>>& parts) {
  fs::create_directories(at);
  for (const auto& [first, frames] : parts) {
    long name = first;
    for (const auto& f : frames)
      fs::create_symlink(fs::absolute(f), at / (std::to_string(name++) + f.extension().string()));
  }
  return at;
}

struct Mapped {
  nlohmann::json map;
  std::string err;
};

Mapped map(const std::string& inputs, const fs::path& out) {
  const auto r = run_cli("map " + inputs + " --out " + out.string() + " --threads 1");
  EXPECT_EQ(r.status, 0) << r.err;
  return {nlohmann::json::parse(read_file(out / "map.json")), r.err};
}

// The frames of the session_break events of `seqtopo map INPUT --online` (events.jsonl).
std::vector<std::size_t> online_breaks(const fs::path& input, const fs::path& out) {
  const auto r = run_cli("map " + input.string() + " --online --no-offline-outputs --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<std::size_t> frames;
  std::istringstream lines(read_file(out / "events.jsonl"));
  for (std::string line; std::getline(lines, line);) {
    const auto e = nlohmann::json::parse(line);
    if (e["event"] == "session_break") {
      EXPECT_EQ(e["i"].get<std::size_t>(), e["frame"].get<std::size_t>());
      EXPECT_GT(e["gap"].get<double>(), 10 * e["median_interval"].get<double>());
      frames.push_back(e["frame"].get<std::size_t>());
    }
  }
  return frames;
}

void expect_same_topology(const nlohmann::json& a, const nlohmann::json& b) {
  EXPECT_EQ(a["labels"], b["labels"]);
  EXPECT_EQ(a["edges"], b["edges"]);
  EXPECT_EQ(a["junctions"], b["junctions"]);
}

TEST(SessionBreaks, TwoRecordingsInOneFolderMapAsTwoSessions) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("maps two worlds of several hundred frames, three times");
  TempDir dir;
  const auto a = world(dir.path, "figure-eight", 2), b = world(dir.path, "corridor-reverse", 2);
  const fs::path one = folder(dir.path / "one", {{0, a}, {10000, b}});
  const fs::path first = folder(dir.path / "a", {{0, a}}), second = folder(dir.path / "b", {{0, b}});
  const Mapped together = map(one.string(), dir.path / "out1");
  const Mapped sessions = map(first.string() + " " + second.string(), dir.path / "out2");
  EXPECT_NE(together.err.find("before image " + std::to_string(a.size()) + " "), std::string::npos) << together.err;
  EXPECT_NE(together.err.find("a session break"), std::string::npos) << together.err;
  const auto& s = together.map["sessions"];
  ASSERT_EQ(s.size(), 2U) << together.map.dump();
  EXPECT_EQ(s[1]["begin"], a.size());
  EXPECT_EQ(s[1]["end"], a.size() + b.size());
  EXPECT_GT(s[1]["break"]["gap"].get<double>(), 100);
  EXPECT_FALSE(s[0].contains("break"));
  expect_same_topology(together.map, sessions.map);
  EXPECT_EQ(together.map["image_sessions"], sessions.map["image_sessions"]);
  // Without the break the last frame of one recording is joined to the first of the other.
  const Mapped joined =
      map(folder(dir.path / "joined", {{0, a}, {static_cast<long>(a.size()), b}}).string(), dir.path / "out3");
  EXPECT_NE(joined.map["edges"], sessions.map["edges"]);
}

TEST(SessionBreaks, ACutInsideAWalkIsFoundAtItsFrameAPauseIsNot) {
  TempDir dir;
#if defined(__SANITIZE_ADDRESS__)
  const std::vector<int> seeds{1};  // the sanitizer pass: one seed (the Release pass runs both)
#else
  const std::vector<int> seeds{1, 3};
#endif
  for (int seed : seeds) {
    const auto w = world(dir.path, "figure-eight", seed);
    const std::vector<fs::path> before(w.begin(), w.begin() + 160), after(w.begin() + 240, w.end());
    const std::vector<fs::path> rest(w.begin() + 160, w.end());
    const std::string tag = std::to_string(seed);
    // Frames 160-239 left out and the names jump: the robot was carried 80 frames on.
    const Mapped cut =
        map(folder(dir.path / ("cut" + tag), {{0, before}, {5000, after}}).string(), dir.path / ("out-cut" + tag));
    EXPECT_NE(cut.err.find("before image 160 "), std::string::npos) << cut.err;
    EXPECT_NE(cut.err.find("a session break"), std::string::npos) << cut.err;
    ASSERT_EQ(cut.map["sessions"].size(), 2U);
    EXPECT_EQ(cut.map["sessions"][1]["begin"], 160);
    // Every frame, with the same jump in the names: a pause.
    const Mapped pause =
        map(folder(dir.path / ("pause" + tag), {{0, before}, {5000, rest}}).string(), dir.path / ("out-pause" + tag));
    EXPECT_NE(pause.err.find("look like neighbours: one session"), std::string::npos) << pause.err;
    EXPECT_FALSE(pause.map.contains("sessions"));
    const Mapped plain = map(folder(dir.path / ("plain" + tag), {{0, w}}).string(), dir.path / ("out-plain" + tag));
    expect_same_topology(pause.map, plain.map);
    // Online, as the frames arrive: the cut is an event at its frame, the pause none.
    EXPECT_EQ(online_breaks(dir.path / ("cut" + tag), dir.path / ("online-cut" + tag)), std::vector<std::size_t>{160});
    EXPECT_EQ(online_breaks(dir.path / ("pause" + tag), dir.path / ("online-pause" + tag)), std::vector<std::size_t>{});
  }
}

TEST(SessionBreaks, NoneInsideAContinuousWalk) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("maps ten walks; the cut and pause test takes the same paths");
  TempDir dir;
  // The corridor: names 1.jpg ... 84.jpg, one second apart.
  const Mapped corridor = map(test_support::corridor_folder().string(), dir.path / "corridor");
  EXPECT_EQ(corridor.err.find("without a frame"), std::string::npos) << corridor.err;
  EXPECT_FALSE(corridor.map.contains("sessions"));
  for (const char* scenario : {"figure-eight", "corridor-reverse", "aliasing"}) {
    for (int seed : {1, 2, 3}) {
      const auto w = world(dir.path, scenario, seed);
      const Mapped m =
          map(w.front().parent_path().string(), dir.path / ("map-" + std::string(scenario) + std::to_string(seed)));
      EXPECT_EQ(m.err.find("without a frame"), std::string::npos) << scenario << seed << m.err;
      EXPECT_FALSE(m.map.contains("sessions")) << scenario << seed;
    }
  }
}

}  // namespace
}  // namespace seqtopo
