// `seqtopo map` as a user runs it: on the bundled corridor data with its ground truth (golden: the
// accuracy must stay within the stated band), deterministic for any thread count (the figures, encoded beside the
// file writes, too), a large matrix drawn as its overview, and clean errors.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "common/cli_run.hpp"
#include "common/corridor_laps.hpp"
#include "common/report_thumbnail.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/outputs/report_options.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/report/html_report.hpp"

namespace {
namespace fs = std::filesystem;

using seqtopo::test_support::read_file;
using seqtopo::test_support::run_cli;

class MapCommand : public ::testing::Test {
 protected:
  const seqtopo::test_support::TempDir dir_;
};

// The one version, CMake's project(VERSION), in --version.
TEST_F(MapCommand, VersionIsTheProjectsOwn) {
  const auto r = run_cli("--version");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "seqtopo " + std::string(seqtopo::version()) + "\n");
  EXPECT_EQ(std::string(seqtopo::version()), SEQTOPO_PROJECT_VERSION);
}

// Band stated in the README: on the bundled corridor the default preset reaches F1 0.977, AUC 0.955
// (precision 1.0). The test allows a small margin for deliberate tuning changes, not for regressions.
TEST_F(MapCommand, BundledCorridorGoldenRun) {
  const fs::path out = dir_.path / "out";
  const auto r = run_cli("map --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"map.json", "alignments.json", "loop_closures.csv", "similarity.npy", "similarity.png",
                           "topology.dot", "topology.svg", "pr_curve.png", "metrics.json", "report.html"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  const auto metrics = nlohmann::json::parse(read_file(out / "metrics.json"));
  const auto& lc = metrics.at("loop_closure");
  EXPECT_GE(lc.at("f1").get<double>(), 0.95);
  EXPECT_GE(lc.at("auc").get<double>(), 0.93);
  EXPECT_GE(lc.at("precision").get<double>(), 0.99);
  EXPECT_GE(lc.at("recall_at_100_precision").get<double>(), 0.93);
  // and the alignment beats the SeqSLAM-style baseline on the same data
  EXPECT_GT(lc.at("auc").get<double>(), metrics.at("baseline").at("auc").get<double>());
  // The version that made them, and in the report with the command line.
  EXPECT_EQ(metrics.at("seqtopo_version").get<std::string>(), seqtopo::version());
  const std::string report = read_file(out / "report.html");
  const std::string provenance =
      "seqtopo " + std::string(seqtopo::version()) + ", run as <code>seqtopo map --out " + out.string() + "</code>";
  EXPECT_NE(report.find(provenance), std::string::npos) << provenance;

  const auto map = nlohmann::json::parse(read_file(out / "map.json"));
  ASSERT_EQ(map.at("images").get<int>(), 84);
  ASSERT_EQ(map.at("labels").size(), 84U);
  // images 41..84 revisit 1..44 (1-based): most revisit images share a label with an early image
  int shared = 0;
  const auto& labels = map.at("labels");
  for (int k = 40; k < 84; ++k) {
    for (int j = 0; j < 44; ++j) shared += labels[k] == labels[j] ? 1 : 0;
  }
  EXPECT_GE(shared, 35);
  for (const auto& p : map.at("edges")) EXPECT_LT(p[0].get<int>(), p[1].get<int>());

  std::istringstream csv(read_file(out / "loop_closures.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "i,j,score,e_value,confidence");
  int rows = 0;
  while (std::getline(csv, line)) {
    int i = 0, j = 0;
    double score = 0, e_value = 0, confidence = -1;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%lf,%lf,%lf", &i, &j, &score, &e_value, &confidence), 5) << line;
    EXPECT_GT(i, j);
    EXPECT_LE(e_value, 0.01) << "every retained pair belongs to a significant alignment";
    EXPECT_GT(confidence, 0.0) << line;
    EXPECT_LE(confidence, 1.0) << line;
    ++rows;
  }
  EXPECT_GT(rows, 30);
  const std::string svg = read_file(out / "topology.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  const std::string html = read_file(out / "report.html");
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  // XML namespace names (the inlined D3 and SVG carry them) are identifiers, never fetched; no other URL.
  std::string text = html;
  for (const std::string ns :
       {"http://www.w3.org/2000/svg", "http://www.w3.org/1999/xhtml", "http://www.w3.org/1999/xlink",
        "http://www.w3.org/2000/xmlns/", "http://www.w3.org/XML/1998/namespace"}) {
    for (auto at = text.find(ns); at != std::string::npos; at = text.find(ns)) text.erase(at, ns.size());
  }
  EXPECT_EQ(text.find("http://"), std::string::npos) << "the report must not load anything from the network";
  EXPECT_EQ(text.find("https://"), std::string::npos) << "the report must not load anything from the network";
  EXPECT_EQ(read_file(out / "similarity.png").substr(1, 3), "PNG");
}

TEST_F(MapCommand, SameOutputsForAnyThreadCount) {
  const fs::path one = dir_.path / "one", two = dir_.path / "two";
  ASSERT_EQ(run_cli("map --threads 1 --out " + one.string()).status, 0);
  ASSERT_EQ(run_cli("map --threads 2 --out " + two.string()).status, 0);
  for (const char* name : {"map.json", "alignments.json", "loop_closures.csv", "similarity.npy", "scores.npy",
                           "metrics.json", "topology.dot", "topology.svg", "similarity.png", "pr_curve.png"}) {
    EXPECT_EQ(read_file(one / name), read_file(two / name)) << name;
  }
}

// The width and height of a PNG, from its IHDR chunk.
std::pair<std::uint32_t, std::uint32_t> png_size(const std::string& png) {
  const auto word = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = v << 8U | static_cast<unsigned char>(png.at(at + k));
    return v;
  };
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  return {word(16), word(20)};
}

// A matrix of more than 2048 images is drawn as its overview of block maxima (2100 images: 2 x 2 scores per
// pixel, 1050 pixels a side plus the axes' margins), with the same bytes for any thread count; a smaller one
// keeps one pixel per image or more (the corridor: 84 images drawn 7 pixels each, 588).
TEST_F(MapCommand, LargeMatrixFigureIsItsBlockMaxOverview) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("a 2100 x 2100 map");
  constexpr std::size_t n = 2100;
  seqtopo::DenseMatrix<float> s(n, n, 0.2F);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.2F, 0.3F);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) s(i, j) = s(j, i) = noise(rng);
  }
  for (std::size_t i = 1200; i < n; ++i) s(i, i - 1200) = s(i - 1200, i) = 0.9F;  // a revisit
  for (std::size_t i = 0; i < n; ++i) s(i, i) = 1.0F;
  seqtopo::io::write_npy(dir_.path / "big.npy", s);
  const fs::path one = dir_.path / "one", two = dir_.path / "two";
  auto r = run_cli("map " + (dir_.path / "big.npy").string() + " --threads 1 --out " + one.string());
  ASSERT_EQ(r.status, 0) << r.err;
  r = run_cli("map " + (dir_.path / "big.npy").string() + " --threads 2 --out " + two.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string png = read_file(one / "similarity.png");
  EXPECT_EQ(png, read_file(two / "similarity.png"));
  const auto [width, height] = png_size(png);
  EXPECT_EQ(width, 78U + 1050U + 118U);  // margins: row axis 78, colour bar 118 (plot/matrix_image.cpp)
  EXPECT_GT(height, 1050U);
  EXPECT_LT(height, 1050U + 200U);
  EXPECT_NE(read_file(one / "report.html").find("each pixel the maximum of a block of 2 x 2 scores"),
            std::string::npos);

  ASSERT_EQ(run_cli("map --threads 2 --out " + (dir_.path / "corridor").string()).status, 0);
  EXPECT_EQ(png_size(read_file(dir_.path / "corridor" / "similarity.png")).first, 78U + 588U + 118U);
}

// The report's thumbnails are made while the run reads the images (outputs::ThumbnailCollector through
// pipeline::MapObserver::on_image): the very data the report would embed from decoding each image again.
TEST_F(MapCommand, ReportThumbnailsFromTheRunAreTheDecodedImages) {
  const fs::path corridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  const fs::path out = dir_.path / "out";
  const auto r = run_cli("map " + corridor.string() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string html = read_file(out / "report.html");
  for (int k = 1; k <= 84; ++k) {
    const std::string uri = seqtopo::test_support::thumbnail_uri(corridor / (std::to_string(k) + ".jpg"),
                                                                 seqtopo::outputs::report_thumbnail_side(84));
    EXPECT_NE(html.find(uri), std::string::npos) << k;
  }
}

// The same with several sessions: each session's images, in the run's order, at its own thumbnail side.
TEST_F(MapCommand, ReportThumbnailsOfSessionsFromTheRunAreEachSessionsImages) {
  const fs::path corridor = seqtopo::test_support::corridor_folder();
  const auto [lap1, lap2] = seqtopo::test_support::corridor_laps(dir_.path);
  const fs::path out = dir_.path / "out";
  const auto r = run_cli("map " + lap1.string() + " " + lap2.string() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string html = read_file(out / "report.html");
  std::size_t at = 0;
  for (int k = 1; k <= 84; ++k) {
    const int side = seqtopo::outputs::report_thumbnail_side(k <= 40 ? 40 : 44);
    at = html.find(seqtopo::test_support::thumbnail_uri(corridor / (std::to_string(k) + ".jpg"), side), at);
    ASSERT_NE(at, std::string::npos) << k;
  }
}

TEST_F(MapCommand, BadInputsGiveOneLineAndNoOutput) {
  const fs::path out = dir_.path / "out";
  seqtopo::io::write_npy(dir_.path / "rect.npy", seqtopo::DenseMatrix<float>(3, 4, 0.5F));
  auto r = run_cli("map " + (dir_.path / "rect.npy").string() + " --input-kind similarity --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err.rfind("seqtopo: error: ", 0), 0U) << r.err;
  EXPECT_NE(r.err.find("square"), std::string::npos) << r.err;

  seqtopo::io::write_npy(dir_.path / "s.npy", seqtopo::DenseMatrix<float>(30, 30, 0.5F));
  std::ofstream(dir_.path / "odo.csv") << "index,x,y,theta\n0,0,0,0\n1,1,0,0\n";
  r = run_cli("map " + (dir_.path / "s.npy").string() + " --odometry " + (dir_.path / "odo.csv").string() + " --out " +
              out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err,
            "seqtopo: error: " + (dir_.path / "odo.csv").string() + ": has 2 poses, the sequence has 30 images\n");

  r = run_cli("map " + (dir_.path / "missing").string() + " --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("missing"), std::string::npos);
  r = run_cli("map --gap -1 --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err.rfind("seqtopo: error: --gap", 0), 0U) << r.err;
  EXPECT_NE(run_cli("map --preset nope --out " + out.string()).status, 0);
  r = run_cli("map --odometry-gate 2 --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err.rfind("seqtopo: error: --odometry-gate: expected BASE,DRIFT", 0), 0U) << r.err;
  r = run_cli("map --odometry-gate 2,-1 --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err.rfind("seqtopo: error: --odometry-gate", 0), 0U) << r.err;
  r = run_cli("map --alignment-set all --out " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err, "seqtopo: error: --alignment-set: expected locally-optimal or non-intersecting, got 'all'\n");

  // nothing was left behind: the output folder is absent or empty
  EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));
}

}  // namespace

namespace {

// --preset paper uses odometry only for the picture: the bundled corridor with odometry that puts every image
// 1 m further along a straight line (so no revisit is possible by it) gives the same map as without, and the
// metric picture; the default preset, whose odometry gate reads the same file, drops the revisit.
TEST_F(MapCommand, PaperPresetUsesOdometryOnlyForThePicture) {
  const fs::path odometry = dir_.path / "straight.csv";
  {
    std::ofstream f(odometry);
    f << "index,x,y,theta\n";
    for (int k = 0; k < 84; ++k) f << k << "," << k << ",0,0\n";
  }
  const fs::path plain = dir_.path / "plain", with = dir_.path / "with", gated = dir_.path / "gated";
  ASSERT_EQ(run_cli("map --preset paper --out " + plain.string()).status, 0);
  const auto r = run_cli("map --preset paper --odometry " + odometry.string() + " --out " + with.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_file(with / "map.json"), read_file(plain / "map.json"));
  EXPECT_EQ(read_file(with / "loop_closures.csv"), read_file(plain / "loop_closures.csv"));
  EXPECT_TRUE(fs::exists(with / "metric_map.png"));
  const auto alignments = nlohmann::json::parse(read_file(with / "alignments.json"));
  EXPECT_TRUE(!alignments.contains("rejected_by_odometry") || alignments.at("rejected_by_odometry").empty());

  ASSERT_EQ(run_cli("map --odometry " + odometry.string() + " --out " + gated.string()).status, 0);
  const auto vetoed = nlohmann::json::parse(read_file(gated / "alignments.json"));
  EXPECT_FALSE(vetoed.at("rejected_by_odometry").empty());
  // A straight line never comes back: each revisit is too far apart by the odometry, and says so.
  for (const auto& a : vetoed.at("rejected_by_odometry")) EXPECT_EQ(a.at("reason"), "apart");
}

}  // namespace

namespace {

// A figure-eight (images 30..39 revisit 10..19, the mapping paper's Fig. 1) given as similarity.npy: map.json
// lists the two junctions with their evidence, topology.dot draws them as junctions, the report carries them.
TEST_F(MapCommand, JunctionsCarryTheirEvidence) {
  constexpr std::size_t n = 50;
  seqtopo::DenseMatrix<float> s(n, n, -0.5F);
  for (std::size_t i = 0; i < n; ++i) {
    s(i, i) = 1.0F;
    if (i + 1 < n) s(i, i + 1) = s(i + 1, i) = 0.5F;
  }
  for (std::size_t k = 0; k < 10; ++k) s(30 + k, 10 + k) = s(10 + k, 30 + k) = 1.0F;
  seqtopo::io::write_npy(dir_.path / "eight.npy", s);
  const fs::path out = dir_.path / "eight";
  const auto r =
      run_cli("map " + (dir_.path / "eight.npy").string() +
              " --input-kind similarity --contrast-window 0 --e-value none --threshold 4 --cap 5 --min-separation 5 "
              "--frames-per-place 1 --out " +
              out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto map = nlohmann::json::parse(read_file(out / "map.json"));
  const auto& labels = map.at("labels");
  ASSERT_EQ(map.at("junctions"), nlohmann::json({labels[10], labels[19]})) << map.dump();
  const auto& evidence = map.at("junction_evidence");
  ASSERT_EQ(evidence.size(), 2U);
  EXPECT_EQ(evidence[0].at("place"), labels[10]);
  EXPECT_EQ(evidence[0].at("images"), nlohmann::json({10, 30}));  // the lead-in and the loop join here
  EXPECT_EQ(evidence[1].at("images"), nlohmann::json({19, 39}));  // the loop and the exit leave here
  EXPECT_EQ(evidence[0].at("branches").size(), 3U);
  EXPECT_EQ(evidence[0].at("passes").size(), 2U);
  EXPECT_EQ(evidence[0].at("passes")[1].at("from"), labels[29]);
  EXPECT_EQ(evidence[0].at("alignments").size(), 1U);
  EXPECT_EQ(evidence[0].at("reasons"), nlohmann::json({"degree", "alignment_boundary"}));
  EXPECT_GT(evidence[0].at("confidence").get<double>(), 0.0);
  EXPECT_LE(evidence[0].at("confidence").get<double>(), 1.0);
  const std::string dot = read_file(out / "topology.dot");
  for (const auto& j : map.at("junctions")) {
    const std::string node = "  p" + std::to_string(j.get<int>()) + " [";
    const auto at = dot.find(node);
    ASSERT_NE(at, std::string::npos) << node;
    EXPECT_NE(dot.substr(at, dot.find('\n', at) - at).find("doublecircle"), std::string::npos);
  }
  const std::string report = read_file(out / "report.html");
  EXPECT_NE(report.find("join / leave images"), std::string::npos);
}

}  // namespace
