// `seqtopo localize` end to end on a small similarity.npy: outputs, the "not in the map" rows, online mode,
// and bad input rejected with one error line and no output left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/cli_run.hpp"
#include "common/corridor_laps.hpp"
#include "common/report_thumbnail.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/outputs/report_options.hpp"

namespace {

namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::read_file;

class LocalizeCli : public ::testing::Test {
 protected:
  static CommandResult localize(const std::string& args) { return seqtopo::test_support::run_cli("localize " + args); }

  // A float32 .npy of rows x cols (format 1.0), written by hand so the test needs no library.
  fs::path write_npy(const std::string& name, std::size_t rows, std::size_t cols, const std::vector<float>& values) {
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                         std::to_string(cols) + "), }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string bytes = "\x93NUMPY";
    bytes += '\x01';
    bytes += '\x00';
    bytes += static_cast<char>(header.size() & 0xFF);
    bytes += static_cast<char>(header.size() >> 8);
    bytes += header;
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    return dir_.write(name, bytes);
  }

  // 50 query frames x 80 map frames: query 0-29 follow map 20-49, query 30-49 are somewhere new.
  fs::path planted() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0F, 0.5F);
    std::vector<float> v(50 * 80);
    for (auto& x : v) x = u(rng);
    for (std::size_t q = 0; q < 30; ++q) v[q * 80 + q + 20] = 1.0F;
    return write_npy("query_x_map_similarity.npy", 50, 80, v);
  }

  const seqtopo::test_support::TempDir dir_;
};

TEST_F(LocalizeCli, WritesMatchesMetricsAndReport) {
  const auto s = planted();
  const auto out = dir_.path / "out";
  const auto r = localize("--map " + s.string() + " --gt same-index --tolerance 0 --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"matches.csv", "metrics.json", "pr_curve.png", "report.html", "similarity.png"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  // query,map,score,confidence,e_value,in_map: every frame has a guess; "not in the map" is the decision.
  const auto read_rows = [](const fs::path& file) {
    std::istringstream csv(read_file(file));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "query,map,score,confidence,e_value,in_map");
    std::vector<std::vector<std::string>> rows;
    while (std::getline(csv, line)) {
      std::vector<std::string> fields;
      std::istringstream in(line);
      for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
      if (!line.empty() && line.back() == ',') fields.emplace_back();
      EXPECT_EQ(fields.size(), 6U) << line;
      rows.push_back(fields);
    }
    return rows;
  };
  const auto rows = read_rows(out / "matches.csv");
  ASSERT_EQ(rows.size(), 50U);
  std::size_t not_in_map = 0;
  for (const auto& f : rows) {
    const std::size_t q = std::stoul(f[0]);
    ASSERT_FALSE(f[1].empty()) << q << ": every frame has a guess";
    const double confidence = std::stod(f[3]);
    EXPECT_EQ(f[5] == "1", confidence >= 0.5) << q;
    if (q >= 2 && q < 28) {
      EXPECT_EQ(std::stoul(f[1]), q + 20) << q;
      EXPECT_EQ(f[5], "1") << q << ": frames on the planted path are in the map";
    }
    not_in_map += f[5] == "0" ? 1 : 0;
  }
  EXPECT_GE(not_in_map, 15U) << "the 20 frames off the map are reported as not in the map";
  // The decision moves with --min-confidence and nothing else.
  for (const char* threshold : {"0", "1"}) {
    const auto again = dir_.path / (std::string("out_") + threshold);
    ASSERT_EQ(
        localize("--map " + s.string() + " --tolerance 0 --min-confidence " + threshold + " --out " + again.string())
            .status,
        0);
    const auto moved = read_rows(again / "matches.csv");
    ASSERT_EQ(moved.size(), rows.size());
    for (std::size_t q = 0; q < rows.size(); ++q) {
      EXPECT_EQ(moved[q][1], rows[q][1]);
      EXPECT_EQ(moved[q][3], rows[q][3]);
      const bool in = std::stod(moved[q][3]) >= std::stod(threshold);
      EXPECT_EQ(moved[q][5], in ? "1" : "0") << threshold << " " << q;
    }
  }
  EXPECT_NE(read_file(out / "metrics.json").find("\"recall_at_100_precision\""), std::string::npos);
}

// The report's thumbnails are made while the run reads the images (outputs::ThumbnailCollector, the query's through
// SimilarityConfig::on_image and the map's through on_column_image): each sequence's own images, in order.
TEST_F(LocalizeCli, ReportThumbnailsFromTheRunAreEachSequencesImages) {
  const fs::path corridor = seqtopo::test_support::corridor_folder();
  // The first lap (1-40) the map, the second (41-84) the query.
  const auto [map, query] = seqtopo::test_support::corridor_laps(dir_.path);
  const fs::path out = dir_.path / "out";
  const auto r = localize("--map " + map.string() + " --query " + query.string() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string html = read_file(out / "report.html");
  const auto uri = [](const fs::path& file, std::size_t frames) {
    return seqtopo::test_support::thumbnail_uri(file, seqtopo::outputs::report_thumbnail_side(frames));
  };
  // The page's data lists the map's thumbnails ("cols"), then the query's ("rows"): each in its sequence's order.
  std::size_t at = 0;
  for (int k = 1; k <= 40; ++k) {
    at = html.find(uri(corridor / (std::to_string(k) + ".jpg"), 40), at);
    ASSERT_NE(at, std::string::npos) << "map image " << k;
  }
  for (int k = 41; k <= 84; ++k) {
    at = html.find(uri(corridor / (std::to_string(k) + ".jpg"), 44), at);
    ASSERT_NE(at, std::string::npos) << "query image " << k;
  }
}

TEST_F(LocalizeCli, OnlinePrintsOneEstimatePerFrame) {
  const auto s = planted();
  const auto r = localize("--map " + s.string() + " --online --out " + (dir_.path / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "query,map,confidence,latency_ms,wait_ms");
  std::size_t n = 0;
  while (std::getline(lines, line)) ++n;
  EXPECT_EQ(n, 50U);
  EXPECT_TRUE(fs::exists(dir_.path / "out" / "latency.csv"));
}

// With --lag, each line answers the frame `lag` frames back (the last ones at the end): one line per frame, in
// order, and the planted revisit's frames found at least as often as at once.
TEST_F(LocalizeCli, OnlineWithALagAnswersEveryFrameOnceInOrder) {
  const auto s = planted();
  const auto right = [](const std::string& out, std::vector<std::size_t>& order) {
    std::istringstream lines(out);
    std::string line;
    std::getline(lines, line);
    std::size_t found = 0;
    while (std::getline(lines, line)) {
      std::istringstream fields(line);
      std::string query, map;
      std::getline(fields, query, ',');
      std::getline(fields, map, ',');
      order.push_back(std::stoul(query));
      if (order.back() < 30 && !map.empty() && std::stoul(map) == order.back() + 20) ++found;
    }
    return found;
  };
  std::vector<std::size_t> at_once, late;
  const auto now = localize("--map " + s.string() + " --online --out " + (dir_.path / "now").string());
  const auto lagged = localize("--map " + s.string() + " --online --lag 5 --out " + (dir_.path / "late").string());
  ASSERT_EQ(now.status, 0) << now.err;
  ASSERT_EQ(lagged.status, 0) << lagged.err;
  const std::size_t found_now = right(now.out, at_once), found_late = right(lagged.out, late);
  ASSERT_EQ(late.size(), 50U);
  for (std::size_t q = 0; q < late.size(); ++q) EXPECT_EQ(late[q], q);
  EXPECT_GE(found_late, found_now);
  EXPECT_GE(found_late, 25U) << lagged.out;
  // The report names the lag among the parameters.
  EXPECT_NE(read_file(dir_.path / "late" / "report.html")
                .find("lag [frames] (each frame answered this many frames "
                      "later)</th><td>5<"),
            std::string::npos);
}

// A query driven at twice the map's speed (query frame q at map frame 2q + 10): found by the default speeds, not by
// the recorded speed alone.
TEST_F(LocalizeCli, FindsAQueryDrivenFasterThanTheMap) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0F, 0.6F);
  std::vector<float> v(40 * 100);
  for (auto& x : v) x = u(rng);
  for (std::size_t q = 0; q < 40; ++q) v[q * 100 + 2 * q + 10] = 0.75F;
  const auto s = write_npy("fast_similarity.npy", 40, 100, v);
  std::string truth = "query,map\n";
  for (std::size_t q = 0; q < 40; ++q) truth += std::to_string(q) + "," + std::to_string(2 * q + 10) + "\n";
  const auto gt = dir_.write("fast.csv", truth);
  const auto recall = [&](const std::string& extra, const std::string& name) {
    const auto out = dir_.path / name;
    const auto r =
        localize("--map " + s.string() + " --gt " + gt.string() + " --tolerance 1" + extra + " --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(read_file(out / "metrics.json")).at("recall_at_1").get<double>();
  };
  EXPECT_GE(recall("", "default"), 0.9);
  EXPECT_LT(recall(" --speeds 1", "recorded"), 0.5);
  EXPECT_GE(recall(" --speeds 1,2", "two"), 0.9);
}

TEST_F(LocalizeCli, RejectsBadInputWithoutLeavingOutput) {
  const auto s = planted();
  const auto out = dir_.path / "out";
  const std::vector<std::string> bad{
      "--map " + s.string() + " --gap -1 --out " + out.string(),
      "--map " + s.string() + " --cap 0 --out " + out.string(),
      "--map " + s.string() + " --lag 3 --out " + out.string(),
      "--map " + s.string() + " --speeds 1,x --out " + out.string(),
      "--map " + s.string() + " --speeds 2,1 --out " + out.string(),
      "--map " + s.string() + " --speeds 1,,2 --out " + out.string(),
      "--map " + s.string() + " --speeds 1,20 --out " + out.string(),
      "--map " + s.string() + " --speeds 1,2 --online --out " + out.string(),
      "--map " + (dir_.path / "missing.npy").string() + " --out " + out.string(),
      "--map " + s.string() + " --query " + dir_.path.string() + " --out " + out.string(),
      "--map " + s.string() + " --gt " + (dir_.path / "missing.csv").string() + " --out " + out.string(),
      "--query - --map " + dir_.path.string() + " --out " + out.string(),
      "--out " + out.string(),
  };
  std::ofstream(dir_.path / "far.csv") << "query,map\n0,500\n";
  std::ofstream(dir_.path / "garbled.csv") << "query,map\n0;1\n";
  std::vector<std::string> all = bad;
  all.push_back("--map " + s.string() + " --gt " + (dir_.path / "garbled.csv").string() + " --out " + out.string());
  for (const auto& args : all) {
    const auto r = localize(args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(r.err.rfind("seqtopo: error: ", 0), 0U) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out / "matches.csv")) << args;
  }
  // A truth that does not fit the sizes is found once they are known, after the localization stage: its
  // progress lines come first, the error is the last line and the only one.
  const auto r =
      localize("--map " + s.string() + " --gt " + (dir_.path / "far.csv").string() + " --out " + out.string());
  EXPECT_NE(r.status, 0);
  std::istringstream lines(r.err);
  std::vector<std::string> err;
  for (std::string line; std::getline(lines, line);) err.push_back(line);
  ASSERT_FALSE(err.empty());
  EXPECT_EQ(err.back().rfind("seqtopo: error: ", 0), 0U) << r.err;
  for (std::size_t k = 0; k + 1 < err.size(); ++k) EXPECT_EQ(err[k].rfind("seqtopo localize: [", 0), 0U) << r.err;
  EXPECT_FALSE(fs::exists(out / "matches.csv"));
}

}  // namespace
