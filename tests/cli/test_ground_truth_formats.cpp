// Ground truth in the formats users have (INTERFACE.md, "Ground truth formats"): the corridor's N x N image
// converted to each of them gives the same metrics.json; mistakes are reported before any work.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/cli_run.hpp"
#include "common/npy_bytes.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/formats/pose_files.hpp"
#include "seqtopo/image/grey_matrix_file.hpp"

namespace {
namespace fs = std::filesystem;

using seqtopo::test_support::read_file;
using seqtopo::test_support::run_cli;

const fs::path kCorridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";

std::string int32(std::int32_t v) {
  std::string s = "J";
  for (int k = 0; k < 4; ++k) s += static_cast<char>((static_cast<std::uint32_t>(v) >> (8 * k)) & 0xFFU);
  return s;
}

// VPR-Bench's ground_truth_new.npy as its Python 2 files are pickled: [query, [map frames]] per row.
std::string vpr_bench_npy(const std::vector<std::vector<std::size_t>>& rows) {
  std::string p =
      "\x80\x02"
      "cnumpy.core.multiarray\n_reconstruct\nq\x01"
      "cnumpy\nndarray\nq\x02";
  p += int32(0) +
       "\x85U\x01"
       "b\x87Rq\x03(" +
       int32(1) + int32(static_cast<std::int32_t>(rows.size())) + int32(2);
  p += "\x86"
       "cnumpy\ndtype\nq\x04U\x02O8" +
       int32(0) + int32(1) + "\x87Rq\x05(" + int32(3) + "U\x01|NNN";
  p += int32(-1) + int32(-1) + int32(63) + "tb\x89]q\x06(";
  for (std::size_t q = 0; q < rows.size(); ++q) {
    p += int32(static_cast<std::int32_t>(q)) + "](";
    for (auto m : rows[q]) p += int32(static_cast<std::int32_t>(m));
    p += "e";
  }
  return seqtopo::test_support::npy_v1_header("|O", rows.size(), 2) + p + "etb.";
}

class GroundTruthFormats : public ::testing::Test {
 protected:
  // metrics.json of mapping `input` against `truth` (extra options appended).
  nlohmann::json metrics(const fs::path& input, const std::string& truth, const std::string& name) {
    const fs::path out = dir_.path / ("out-" + name);
    const auto r = run_cli("map " + input.string() + " --ground-truth " + truth + " --out " + out.string());
    EXPECT_EQ(r.status, 0) << name << ": " << r.err;
    return nlohmann::json::parse(read_file(out / "metrics.json"));
  }

  // The relation as rows (i, its partners) of `images` images, from the pixels of an N x N image.
  static std::vector<std::vector<std::size_t>> rows_of(const seqtopo::DenseMatrix<std::uint8_t>& m) {
    std::vector<std::vector<std::size_t>> rows(m.rows);
    for (std::size_t i = 0; i < m.rows; ++i) {
      for (std::size_t j = 0; j < m.cols; ++j) {
        if (m(i, j) != 0) rows[i].push_back(j);
      }
    }
    return rows;
  }

  // Every format of the same relation, written beside each other.
  std::vector<std::pair<std::string, fs::path>> conversions(const seqtopo::DenseMatrix<std::uint8_t>& m) {
    const auto rows = rows_of(m);
    std::string pairs = "query,map\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (auto j : rows[i]) pairs += std::to_string(i) + "," + std::to_string(j) + "\n";
    }
    std::string matrix = seqtopo::test_support::npy_v1_header("|u1", m.rows, m.cols);
    for (std::size_t i = 0; i < m.rows; ++i) {
      for (std::size_t j = 0; j < m.cols; ++j) matrix += static_cast<char>(m(i, j) != 0 ? 1 : 0);
    }
    return {{"pairs", dir_.write("pairs.csv", pairs)},
            {"vpr-bench", dir_.write("ground_truth_new.npy", vpr_bench_npy(rows))},
            {"matrix-npy", dir_.write("same_place.npy", matrix)}};
  }

  // The similarity of the corridor, mapped once, is the input of every run (faster than the images).
  fs::path corridor_similarity() {
    const fs::path out = dir_.path / "similarity";
    const auto r = run_cli("map " + kCorridor.string() + " --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return out / "similarity.npy";
  }

  const seqtopo::test_support::TempDir dir_;
};

TEST_F(GroundTruthFormats, EveryFormatOfTheCorridorsTruthGivesTheSameMetrics) {
  const fs::path input = corridor_similarity();
  const fs::path image = kCorridor / "ground_truth.bmp";
  const auto expected = metrics(input, image.string(), "image");
  ASSERT_GT(expected.at("loop_closure").at("tp").get<int>(), 0);
  for (const auto& [name, file] : conversions(seqtopo::image::read_grey_matrix_image(image))) {
    EXPECT_EQ(metrics(input, file.string(), name), expected) << name;
  }
}

TEST_F(GroundTruthFormats, PosesCsvTumAndKittiWithARadiusGiveTheImagesMetrics) {
  const fs::path input = corridor_similarity();
  // A route walked twice along x: frame i at x = i, frames 40.. back at x = i - 40 (the corridor's revisit),
  // with a little sideways offset so that y matters; same place within 1.5 m.
  std::vector<std::pair<double, double>> xy;
  for (int i = 0; i < 84; ++i) xy.emplace_back(i < 40 ? i : i - 40, i < 40 ? 0.0 : 0.25);
  seqtopo::DenseMatrix<std::uint8_t> same(84, 84);
  std::string csv = "index,x,y,theta\n", tum, kitti;
  for (std::size_t i = 0; i < 84; ++i) {
    for (std::size_t j = 0; j < 84; ++j) {
      const double dx = xy[i].first - xy[j].first, dy = xy[i].second - xy[j].second;
      same(i, j) = dx * dx + dy * dy <= 1.5 * 1.5 ? 255 : 0;
    }
    const auto x = std::to_string(xy[i].first), y = std::to_string(xy[i].second);
    csv += std::to_string(i) + "," + x + "," + y + ",0\n";
    tum += std::to_string(i) + " " + x + " " + y + " 0 0 0 0 1\n";
    // KITTI's camera frame: planar (x, y) = (tz, -tx).
    kitti += "1 0 0 " + std::to_string(-xy[i].second) + " 0 1 0 0 0 0 1 " + x + "\n";
  }
  std::string pgm = "P5\n84 84\n255\n";
  for (std::size_t i = 0; i < 84; ++i) {
    for (std::size_t j = 0; j < 84; ++j) pgm += static_cast<char>(same(i, j));
  }
  const auto expected = metrics(input, dir_.write("same.pgm", pgm).string(), "image");
  ASSERT_GT(expected.at("loop_closure").at("tp").get<int>(), 0);
  for (const auto& [name, text] :
       {std::pair{"poses.csv", csv}, std::pair{"poses_tum.txt", tum}, std::pair{"poses_kitti.txt", kitti}}) {
    EXPECT_EQ(metrics(input, dir_.write(name, text).string() + " --gt-radius 1.5", name), expected) << name;
  }
}

// Mistakes cost one line and no work: nothing is written, stderr holds only the error.
TEST_F(GroundTruthFormats, MistakesAreReportedBeforeAnyWork) {
  const fs::path out = dir_.path / "out";
  const auto one_error = [&](const std::string& args, const std::string& expected) {
    const auto r = run_cli(args + " --out " + out.string());
    EXPECT_EQ(r.status, 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err, "seqtopo: error: " + expected + "\n") << args;
    EXPECT_FALSE(fs::exists(out)) << args;
  };
  std::string small = "P5\n10 10\n255\n" + std::string(100, '\0');
  const auto wrong_size = dir_.write("small.pgm", small);
  one_error("map " + kCorridor.string() + " --ground-truth " + wrong_size.string(),
            wrong_size.string() + ": is 10 x 10, the sequence has 84 images");
  const auto poses = dir_.write("poses.csv", "index,x,y\n0,0,0\n");
  one_error("map " + kCorridor.string() + " --gt " + poses.string(),
            "--gt-radius: needed (> 0) with a poses ground truth (" + poses.string() +
                "): images within the radius [m] of each other are the same place");
  const auto far = dir_.write("far.csv", "query,map\n0,1\n90,3\n");
  one_error("map " + kCorridor.string() + " --ground-truth " + far.string(),
            far.string() +
                ": lists image 90, the sequence has 84 images (0 to 83; pairs and VPR-Bench rows name "
                "the images kept)");
  one_error("localize --map " + kCorridor.string() + " --query " + kCorridor.string() + " --gt same_index",
            "--ground-truth: unknown ground-truth keyword 'same_index', expected one of same-index (or a file)");
  one_error("map " + kCorridor.string() + " --ground-truth same-index",
            "--ground-truth: unknown ground-truth keyword 'same-index': give a file (an N x N image or .npy, a pairs "
            "CSV, VPR-Bench .npy, poses)");
}

// A pairs file lists the true frames themselves: --tolerance does not widen them unless it is given.
TEST_F(GroundTruthFormats, LocalizeTakesThePairsAsListedUnlessAToleranceIsGiven) {
  // 40 query x 60 map frames: query q was taken at map frame q + 10.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0F, 0.5F);
  std::vector<float> v(40 * 60);
  for (auto& x : v) x = u(rng);
  for (std::size_t q = 0; q < 40; ++q) v[q * 60 + q + 10] = 1.0F;
  std::string npy = seqtopo::test_support::npy_v1_header("<f4", 40, 60);
  npy.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  const auto s = dir_.write("similarity.npy", npy);
  // The truth lists one frame beside the one found.
  std::string pairs = "query,map\n";
  for (std::size_t q = 0; q < 40; ++q) pairs += std::to_string(q) + "," + std::to_string(q + 11) + "\n";
  const auto truth = dir_.write("pairs.csv", pairs);
  const auto recall = [&](const std::string& extra, const std::string& name) {
    const auto out = dir_.path / name;
    const auto r = run_cli("localize --map " + s.string() + " --ground-truth " + truth.string() + extra + " --out " +
                           out.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(read_file(out / "metrics.json")).at("recall_at_1").get<double>();
  };
  EXPECT_EQ(recall("", "as-listed"), 0.0);
  EXPECT_GT(recall(" --tolerance 1", "widened"), 0.8);
  // The answers do not depend on the truth given: a file, same-index or none, the same matches.csv (the confidence
  // of a guess within 2 frames, the map's, unless --tolerance says otherwise).
  const auto matches = [&](const std::string& extra, const std::string& name) {
    const auto out = dir_.path / name;
    const auto r = run_cli("localize --map " + s.string() + extra + " --out " + out.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return read_file(out / "matches.csv");
  };
  const std::string alone = matches("", "alone");
  EXPECT_EQ(matches(" --ground-truth " + truth.string(), "with-file"), alone);
  EXPECT_EQ(matches(" --ground-truth same-index", "with-same-index"), alone);
  EXPECT_NE(matches(" --ground-truth " + truth.string() + " --tolerance 0", "tolerance-0"), alone);
}

// The data block of a report.html.
nlohmann::json report_data(const fs::path& report) {
  const std::string html = read_file(report);
  const std::string open = "<script type=\"application/json\" id=\"seqtopo-data\">";
  const auto begin = html.find(open);
  if (begin == std::string::npos) return nullptr;
  const auto end = html.find("</script>", begin);
  return nlohmann::json::parse(html.substr(begin + open.size(), end - begin - open.size()));
}

std::size_t thumbnails(const nlohmann::json& data) {
  std::size_t k = 0;
  for (const auto& t : data["sequences"]["rows"]["thumbnails"]) k += t.is_string() ? 1 : 0;
  return k;
}

// A map with errors (a tight E-value misses revisits; a loose one lets chance alignments in): they are counted as
// metrics.json counts them, marked on the matrix and listed with their images; a similarity.npy input shows the
// images given with --images.
TEST_F(GroundTruthFormats, TheReportShowsWhereTheMapIsWrongWithTheImages) {
  const fs::path input = corridor_similarity();
  for (const char* e_value : {"1e-9", "1000"}) {
    const fs::path out = dir_.path / (std::string("errors-") + e_value);
    const auto r = run_cli("map " + input.string() + " --images " + kCorridor.string() + " --e-value " + e_value +
                           " --ground-truth " + (kCorridor / "ground_truth.bmp").string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto metrics = nlohmann::json::parse(read_file(out / "metrics.json")).at("loop_closure");
    const auto data = report_data(out / "report.html");
    ASSERT_TRUE(data.is_object()) << e_value;
    EXPECT_EQ(data["errors"]["false_positives"].size(), metrics.at("fp").get<std::size_t>()) << e_value;
    EXPECT_EQ(data["errors"]["missed"].size(), metrics.at("fn").get<std::size_t>()) << e_value;
    EXPECT_EQ(thumbnails(data), 84U) << e_value;
    const std::string html = read_file(out / "report.html");
    EXPECT_NE(html.find("Where the map is wrong"), std::string::npos);
    const std::size_t fp = metrics.at("fp").get<std::size_t>(), fn = metrics.at("fn").get<std::size_t>();
    std::size_t listed = 0;
    for (auto at = html.find("class=\"error-thumb\""); at != std::string::npos;
         at = html.find("class=\"error-thumb\"", at + 1))
      ++listed;
    EXPECT_EQ(listed, 2 * (std::min<std::size_t>(fp, 50) + std::min<std::size_t>(fn, 50))) << e_value;
  }
}

// Several sessions show their images too; with odometry the corrected trajectory is written as TUM and KITTI.
TEST_F(GroundTruthFormats, SessionsShowTheirImagesAndTheTrajectoryIsWritten) {
  const fs::path a = dir_.path / "first", b = dir_.path / "second";
  fs::create_directories(a);
  fs::create_directories(b);
  std::string odometry_a = "index,x,y,theta\n", odometry_b = odometry_a;
  for (int k = 1; k <= 84; ++k) {
    const auto name = std::to_string(k) + ".jpg";
    fs::create_symlink(kCorridor / name, (k <= 44 ? a : b) / name);
    const int local = k <= 44 ? k - 1 : k - 45;
    (k <= 44 ? odometry_a : odometry_b) += fmt::format("{},{},{},0\n", local, local * 0.5, k <= 44 ? 0.0 : 0.3);
  }
  const fs::path out = dir_.path / "sessions";
  const auto r =
      run_cli("map " + a.string() + " " + b.string() + " --odometry " + dir_.write("odo_a.csv", odometry_a).string() +
              " --odometry " + dir_.write("odo_b.csv", odometry_b).string() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(thumbnails(report_data(out / "report.html")), 84U);
  const auto tum = seqtopo::formats::read_pose_file(out / "trajectory_tum.txt");
  const auto kitti = seqtopo::formats::read_pose_file(out / "trajectory_kitti.txt");
  EXPECT_EQ(tum.kind, seqtopo::formats::PoseFileKind::tum);
  ASSERT_EQ(tum.timed.size(), 84U);
  ASSERT_EQ(kitti.per_frame.size(), 84U);
  for (std::size_t k = 0; k < 84; ++k) {
    EXPECT_EQ(tum.timed[k].time, static_cast<double>(k));
    EXPECT_NEAR(tum.timed[k].pose.x, kitti.per_frame[k].x, 1e-6);
    EXPECT_NEAR(tum.timed[k].pose.y, kitti.per_frame[k].y, 1e-6);
  }
}

}  // namespace
