// `seqtopo map --streaming` as a user runs it: on descriptors.npy it gives the same map, alignments and
// loop closures as the dense command aligning the same scores; it refuses, in one line and without
// output, whatever needs the N x N matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "common/cli_run.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::DenseMatrix;
using seqtopo::test_support::read_file;
using seqtopo::test_support::run_cli;

// A walk through descriptor space that comes back over an earlier part forward (frames n/2 .. n/2 + n/5
// repeat 0 .. n/5) and another backward (the next n/5 frames repeat 3n/10 .. n/10 in reverse).
DenseMatrix<float> walk_descriptors(std::size_t n, std::size_t dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  DenseMatrix<float> x(n, dim);
  for (std::size_t t = 0; t < dim; ++t) x(0, t) = noise(rng);
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t t = 0; t < dim; ++t) {
      float base = x(i - 1, t);
      if (i >= n / 2 && i < n / 2 + n / 5) base = x(i - n / 2, t);
      if (i >= n / 2 + n / 5 && i < n / 2 + 2 * (n / 5)) base = x(n - i, t);
      x(i, t) = base + 0.4F * noise(rng);
    }
  }
  return x;
}

// The true place of frame i in the walk above: the frame it repeats, else itself.
std::size_t true_place(std::size_t i, std::size_t n) {
  if (i >= n / 2 && i < n / 2 + n / 5) return i - n / 2;
  if (i >= n / 2 + n / 5 && i < n / 2 + 2 * (n / 5)) return n - i;
  return i;
}

class MapStreaming : public ::testing::Test {
 protected:
  // descriptors.npy of the walk, and the cosine matrix the streamed score starts from (float dot products
  // of the normalised rows, StreamingSimilarity::cosine) as a similarity.npy: the dense command on it
  // aligns enhance_contrast_symmetric(cosine), which the streamed score equals bit for bit.
  void write_walk(std::size_t n, std::size_t dim) {
    const auto x = walk_descriptors(n, dim, 11);
    seqtopo::io::write_npy(path("walk.npy"), x);
    const seqtopo::scale::StreamingSimilarity streamed(x.values, n, dim);
    DenseMatrix<float> cosine(n, n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) cosine(i, j) = streamed.cosine(i, j);
    }
    seqtopo::io::write_npy(path("cosine.npy"), cosine);
    std::ofstream poses(path("poses.csv")), places(path("places.csv")), odometry(path("odometry.csv"));
    poses << "index,x,y\n";
    places << "index,place\n";
    odometry << "index,dx,dy,dtheta\n";
    for (std::size_t i = 0; i < n; ++i) {
      poses << i << "," << true_place(i, n) << ",0\n";
      places << i << "," << true_place(i, n) << "\n";
      odometry << i << "," << (i == 0 ? 0 : 1) << ",0,0\n";
    }
  }
  std::string path(const std::string& name) const { return (dir_.path / name).string(); }

  seqtopo::test_support::TempDir dir_;
};

TEST_F(MapStreaming, SameMapAsTheDenseCommandOnTheSameScores) {
  const std::size_t n = 360;
  write_walk(n, 24);
  auto r = run_cli("map " + path("walk.npy") + " --streaming --out " + path("streamed"));
  ASSERT_EQ(r.status, 0) << r.err;
  r = run_cli("map " + path("cosine.npy") + " --input-kind similarity --engine fast --out " + path("dense"));
  ASSERT_EQ(r.status, 0) << r.err;
  const fs::path streamed = path("streamed"), dense = path("dense");
  // None of these files holds a timing: byte for byte. similarity.png too: below 2048 images the overview
  // is the score matrix itself.
  for (const char* name : {"map.json", "alignments.json", "loop_closures.csv", "topology.dot", "similarity.png"}) {
    ASSERT_TRUE(fs::exists(streamed / name)) << name;
    EXPECT_EQ(read_file(streamed / name), read_file(dense / name)) << name;
  }
  const auto map = nlohmann::json::parse(read_file(streamed / "map.json"));
  EXPECT_EQ(map.at("images").get<std::size_t>(), n);
  EXPECT_GE(map.at("alignments").size(), 2U) << "the walk has a forward and a reverse revisit";
  EXPECT_FALSE(fs::exists(streamed / "scores.npy"));
  EXPECT_FALSE(fs::exists(streamed / "similarity.npy"));
  EXPECT_TRUE(fs::exists(streamed / "report.html"));

  // What the dense command aligned is what the streamed similarity computes, cell for cell, with the contrast
  // window and offset the run decided (alignments.json "significance").
  const auto decided = nlohmann::json::parse(read_file(streamed / "alignments.json")).at("significance");
  const auto scores = seqtopo::io::read_npy_matrix<float>(dense / "scores.npy");
  const auto x = seqtopo::io::read_npy_matrix<float>(path("walk.npy"));
  const seqtopo::scale::StreamingSimilarity similarity(
      x.values, n, x.cols,
      {.contrast_window = decided.at("contrast_window").get<std::size_t>(),
       .contrast_offset = decided.at("contrast_offset").get<float>()});
  std::vector<float> row(n);
  for (std::size_t i = 0; i < n; ++i) {
    similarity.read_row(i, 0, n, row.data());
    for (std::size_t j = 0; j < n; ++j) ASSERT_EQ(row[j], scores(i, j)) << i << ", " << j;
  }

  // and the result does not depend on the thread count
  r = run_cli("map " + path("walk.npy") + " --streaming --threads 1 --out " + path("one"));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"map.json", "alignments.json", "loop_closures.csv", "similarity.png"}) {
    EXPECT_EQ(read_file(fs::path(path("one")) / name), read_file(streamed / name)) << name;
  }
}

TEST_F(MapStreaming, GroundTruthOdometryAndReport) {
  const std::size_t n = 300;
  write_walk(n, 16);
  const std::string truth = " --ground-truth " + path("poses.csv") + " --gt-radius 2 --gt-places " +
                            path("places.csv") + " --odometry " + path("odometry.csv") + " --odometry-gate none";
  auto r = run_cli("map " + path("walk.npy") + " --streaming" + truth + " --out " + path("streamed"));
  ASSERT_EQ(r.status, 0) << r.err;
  r = run_cli("map " + path("cosine.npy") + " --input-kind similarity --engine fast" + truth + " --out " +
              path("dense"));
  ASSERT_EQ(r.status, 0) << r.err;
  const fs::path streamed = path("streamed");
  for (const char* name : {"metric_map.png", "pr_curve.png", "metrics.json", "report.html"}) {
    EXPECT_TRUE(fs::exists(streamed / name)) << name;
  }
  const auto metrics = nlohmann::json::parse(read_file(streamed / "metrics.json"));
  const auto dense_metrics = nlohmann::json::parse(read_file(fs::path(path("dense")) / "metrics.json"));
  EXPECT_TRUE(metrics.at("streaming").get<bool>());
  EXPECT_FALSE(dense_metrics.contains("streaming"));
  EXPECT_FALSE(metrics.contains("baseline"));
  EXPECT_NE(metrics.at("baseline_skipped").get<std::string>().find("N x N"), std::string::npos);
  EXPECT_EQ(metrics.at("loop_closure"), dense_metrics.at("loop_closure"));
  EXPECT_EQ(metrics.at("topology"), dense_metrics.at("topology"));
  EXPECT_GT(metrics.at("loop_closure").at("tp").get<int>(), 0);

  const std::string html = read_file(streamed / "report.html");
  EXPECT_NE(html.find("streaming"), std::string::npos);
  EXPECT_NE(html.find("Timings"), std::string::npos);
  EXPECT_NE(html.find("alignment (similarity streamed)"), std::string::npos);
  EXPECT_NE(html.find("not run with --streaming"), std::string::npos);
}

TEST_F(MapStreaming, SyntheticRouteOfTheBenchmarkMapsItsRevisits) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("a long synthetic route");
  // `seqtopo bench scale --write-route` writes the route BENCHMARK.md maps at 10^5 frames, with its truth.
  auto r = run_cli("bench scale --sizes 3000 --write-route " + path("route"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(seqtopo::io::read_npy_header(path("route") + "/descriptors.npy").shape,
            (std::vector<std::size_t>{3000, 64}));
  r = run_cli("map " + path("route") + "/descriptors.npy --streaming --ground-truth " + path("route") +
              "/poses.csv --gt-radius 5 --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto metrics = nlohmann::json::parse(read_file(fs::path(path("out")) / "metrics.json"));
  // Its consecutive places look almost as alike as a revisit, so alignments land a few frames off.
  EXPECT_GT(metrics.at("loop_closure").at("recall").get<double>(), 0.5);
  EXPECT_GT(metrics.at("loop_closure").at("precision").get<double>(), 0.9);
  r = run_cli("bench scale --sizes 300,600 --write-route " + path("two"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--write-route"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("two") + "/descriptors.npy"));
}

TEST_F(MapStreaming, LargeSequenceGetsABlockMaxOverview) {
  const std::size_t n = 2300;  // above 2048: the overview takes 2 x 2 blocks
  write_walk(n, 8);
  const auto r = run_cli("map " + path("walk.npy") + " --streaming --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string png = read_file(fs::path(path("out")) / "similarity.png");
  ASSERT_GE(png.size(), 24U);
  auto be32 = [&](std::size_t at) {
    return (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at])) << 24U) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 1])) << 16U) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 2])) << 8U) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 3]));
  };
  // The overview is (n + 1) / 2 cells a side, drawn one pixel each inside the figure's axes, colour bar and legend.
  EXPECT_GT(be32(16), (n + 1) / 2);  // IHDR width
  EXPECT_LT(be32(16), (n + 1) / 2 + 300);
  EXPECT_GT(be32(20), (n + 1) / 2);  // IHDR height
  EXPECT_LT(be32(20), (n + 1) / 2 + 200);
  EXPECT_NE(read_file(fs::path(path("out")) / "report.html").find("block of 2 x 2 scores"), std::string::npos);
}

TEST_F(MapStreaming, ImageFolderWithOneVectorDescriptor) {
  const std::string corridor = std::string(SEQTOPO_SOURCE_DIR) + "/data/rtabmap-corridor";
  const auto r = run_cli("map " + corridor + " --streaming --descriptor patch --metric cosine --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto map = nlohmann::json::parse(read_file(fs::path(path("out")) / "map.json"));
  EXPECT_EQ(map.at("images").get<int>(), 84);
  EXPECT_FALSE(map.at("alignments").empty());
}

// Dark frames carry no evidence of a revisit whatever the engine: the corridor with 20 black frames after each
// lap, streamed, sparse and online, lists the frames the dense map masks (alignments.json's low_information_frames)
// and says so.
TEST_F(MapStreaming, DarkFramesAreMaskedAsInTheDenseMap) {
  const fs::path corridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  const fs::path frames = dir_.path / "frames";
  fs::create_directories(frames);
  const auto probe = seqtopo::image::load_image(corridor / "1.jpg");
  const seqtopo::RgbImage black(probe.width, probe.height, 0);
  int k = 0;
  const auto add = [&](const seqtopo::RgbImage& image) {
    seqtopo::plot::write_png(frames / (std::to_string(++k) + ".png"), image);
  };
  for (int lap = 0; lap < 2; ++lap) {
    for (int f = lap == 0 ? 1 : 41; f <= (lap == 0 ? 40 : 84); ++f) {
      add(seqtopo::image::load_image(corridor / (std::to_string(f) + ".jpg")));
    }
    for (int d = 0; d < 20; ++d) add(black);
  }
  const auto low_information = [&](const std::string& engine) {
    const fs::path out = dir_.path / engine;
    const auto r = run_cli("map " + frames.string() + " --descriptor patch --metric cosine --engine " + engine +
                           " --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("little information"), std::string::npos) << engine << ": " << r.err;
    const auto significance = nlohmann::json::parse(read_file(out / "alignments.json")).at("significance");
    return significance.value("low_information_frames", std::vector<std::size_t>{});
  };
  const auto dense = low_information("exact");
  ASSERT_EQ(dense.size(), 40U);  // the black frames: 40-59 and 104-123
  EXPECT_EQ(dense.front(), 40U);
  EXPECT_EQ(dense.back(), 123U);
  EXPECT_EQ(low_information("streaming"), dense);
  EXPECT_EQ(low_information("sparse"), dense);
  // Online, judged as the frames arrive (the median so far): the same frames, in online.json and on stderr.
  const fs::path online = dir_.path / "online";
  const auto r = run_cli("map " + frames.string() + " --online --no-offline-outputs --out " + online.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("images of little information"), std::string::npos) << r.err;
  const auto significance = nlohmann::json::parse(read_file(online / "online.json")).at("significance");
  EXPECT_EQ(significance.value("low_information_frames", std::vector<std::size_t>{}), dense);
}

// Without --descriptor / --metric, images stream the nearest vector descriptor (patch, by cosine), and say so:
// the same map as when both are given.
TEST_F(MapStreaming, ImageFolderStreamsTheNearestVectorDescriptor) {
  const std::string corridor = std::string(SEQTOPO_SOURCE_DIR) + "/data/rtabmap-corridor";
  const auto chosen = run_cli("map " + corridor + " --streaming --out " + path("chosen"));
  ASSERT_EQ(chosen.status, 0) << chosen.err;
  EXPECT_NE(chosen.err.find("images compared by the patch descriptor's cosine"), std::string::npos) << chosen.err;
  const auto given =
      run_cli("map " + corridor + " --streaming --descriptor patch --metric cosine --out " + path("given"));
  ASSERT_EQ(given.status, 0) << given.err;
  EXPECT_EQ(given.err.find("descriptor's cosine"), std::string::npos) << given.err;  // nothing was changed
  for (const char* file : {"map.json", "alignments.json", "loop_closures.csv"})
    EXPECT_EQ(read_file(fs::path(path("chosen")) / file), read_file(fs::path(path("given")) / file)) << file;
}

// No engine given and a small machine (SEQTOPO_MEMORY_LIMIT): the run streams, the same map as --streaming, and
// says why in one line; an engine given is used as is. (Budgets around each engine's peak: test_engine_choice.cpp.)
// 6,000 frames, so that the tables, not the process itself (larger under the sanitizers), decide at 1 GB.
TEST_F(MapStreaming, EngineChosenByTheMemoryTheRunNeeds) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("large maps under several memory limits");
  write_walk(6000, 8);
  const std::string walk = path("walk.npy");
  ASSERT_EQ(setenv("SEQTOPO_MEMORY_LIMIT", "1G", 1), 0);
  const auto small = run_cli("map " + walk + " --out " + path("small"));
  unsetenv("SEQTOPO_MEMORY_LIMIT");
  ASSERT_EQ(small.status, 0) << small.err;
  EXPECT_NE(small.err.find("engine streaming: "), std::string::npos) << small.err;
  const auto forced = run_cli("map " + walk + " --streaming --out " + path("forced"));
  ASSERT_EQ(forced.status, 0) << forced.err;
  EXPECT_EQ(forced.err.find("engine "), std::string::npos) << forced.err;
  EXPECT_EQ(read_file(fs::path(path("small")) / "map.json"), read_file(fs::path(path("forced")) / "map.json"));
}

// --sparse aligns only the candidates (each frame's nearest neighbours) and -1 elsewhere: with enough neighbours
// to cover both revisits, the same loop closures as the streamed map of every pair; with --neighbours it is
// refused without --sparse.
TEST_F(MapStreaming, SparseEqualsStreamedWhereTheCandidatesCoverTheRevisits) {
  write_walk(600, 8);
  const std::string walk = path("walk.npy"), truth = " --ground-truth " + path("poses.csv") + " --gt-radius 0.5";
  const auto streamed = run_cli("map " + walk + " --streaming" + truth + " --out " + path("streamed"));
  ASSERT_EQ(streamed.status, 0) << streamed.err;
  const auto sparse = run_cli("map " + walk + " --sparse --neighbours 40" + truth + " --out " + path("sparse"));
  ASSERT_EQ(sparse.status, 0) << sparse.err;
  EXPECT_NE(sparse.err.find("candidate pairs (40 nearest neighbours per frame, diagonals 0 frames around them)"),
            std::string::npos)
      << sparse.err;
  EXPECT_EQ(read_file(fs::path(path("sparse")) / "loop_closures.csv"),
            read_file(fs::path(path("streamed")) / "loop_closures.csv"));
  const auto scored = [&](const char* run) {
    return nlohmann::json::parse(read_file(fs::path(path(run)) / "metrics.json")).at("loop_closure");
  };
  EXPECT_GT(scored("sparse").at("tp").get<int>(), 100);  // both revisits found
  EXPECT_EQ(scored("sparse").at("f1"), scored("streamed").at("f1"));
  const auto refused = run_cli("map " + walk + " --neighbours 5 --out " + path("refused"));
  EXPECT_NE(refused.status, 0);
  EXPECT_EQ(refused.err.rfind("seqtopo: error: --neighbours: ", 0), 0U) << refused.err;
  const auto reach = run_cli("map " + walk + " --diagonal-reach 5 --out " + path("refused"));
  EXPECT_NE(reach.status, 0);
  EXPECT_EQ(reach.err.rfind("seqtopo: error: --diagonal-reach: ", 0), 0U) << reach.err;
}

// A revisit seen with much noise (frames 400-549 repeat 100-249, noise 2.5 times the texture's): a frame's
// nearest neighbour is seldom its true match, so the candidates miss most of the revisit; the diagonals around
// them (--diagonal-reach) bring its other pairs back, as a revisit under appearance change needs.
TEST_F(MapStreaming, SparseDiagonalsAroundFewCandidatesRecoverTheRevisits) {
  const std::size_t n = 600, dim = 32;
  std::mt19937 random(5);
  std::normal_distribution<float> normal;
  DenseMatrix<float> x(n, dim);
  std::ofstream poses(path("poses.csv"));
  poses << "index,x,y\n";
  for (std::size_t i = 0; i < n; ++i) {
    const bool revisit = i >= 400 && i < 550;
    for (std::size_t d = 0; d < dim; ++d) x(i, d) = revisit ? x(i - 300, d) + 2.5F * normal(random) : normal(random);
    poses << i << "," << (revisit ? i - 300 : i) << ",0\n";
  }
  poses.close();
  seqtopo::io::write_npy(path("noisy.npy"), x);
  const std::string truth = " --ground-truth " + path("poses.csv") + " --gt-radius 0.5";
  const auto found = [&](const std::string& options, const char* out) {
    const auto run =
        run_cli("map " + path("noisy.npy") + " --sparse --neighbours 1" + options + truth + " --out " + path(out));
    EXPECT_EQ(run.status, 0) << run.err;
    return nlohmann::json::parse(read_file(fs::path(path(out)) / "metrics.json"))
        .at("loop_closure")
        .at("tp")
        .get<int>();
  };
  const int alone = found("", "alone"), grown = found(" --diagonal-reach 10", "grown");
  EXPECT_LT(alone, 100) << "the nearest neighbours alone find the revisit: the test shows nothing";
  EXPECT_GT(grown, 140) << alone << " -> " << grown;
}

TEST_F(MapStreaming, RefusesWhatNeedsTheMatrixInOneLine) {
  write_walk(60, 8);
  const std::string corridor = std::string(SEQTOPO_SOURCE_DIR) + "/data/rtabmap-corridor";
  const std::string walk = path("walk.npy");
  const std::string bmp = corridor + "/ground_truth.bmp";
  const std::pair<std::string, std::string> cases[] = {
      {path("cosine.npy") + " --input-kind similarity", "--streaming"},
      {walk + " --engine exact", "--engine"},
      {walk + " --metric chi2", "--metric"},
      {walk + " --metric l1", "--metric"},
      {walk + " --preset paper", "--preset"},
      {walk + " --descriptor joint-histogram,patch", "--descriptor"},
      {walk + " --contrast-window 0", "--contrast-window"},
      {walk + " --kappa 2", "--kappa"},
      {walk + " --ground-truth " + bmp, "--ground-truth"},
      {walk + " --ground-truth " + path("poses.csv"), "--gt-radius"},
      {corridor + " --descriptor joint-histogram --metric cosine", "--descriptor"},
  };
  const fs::path out = path("out");
  for (const auto& [args, subject] : cases) {
    const auto r = run_cli("map " + args + " --streaming --out " + out.string());
    EXPECT_NE(r.status, 0) << args;
    EXPECT_EQ(r.err.rfind("seqtopo: error: " + subject + ": ", 0), 0U) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out)) << args;
  }
}

}  // namespace
