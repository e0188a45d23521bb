// Command-line details a new user meets first (issue #22): the help names the program, parse errors point to the
// subcommand's help, `map --help` lists every descriptor, `align` reads soft-masked FASTA by letter, has a view for
// reading and a default threshold above chance, `match-strings` writes its header first and says what its
// geometric rates are over.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/plot/png.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::read_file;
using seqtopo::test_support::run_cli;
using seqtopo::test_support::run_command;
using seqtopo::test_support::TempDir;

std::string random_dna(std::size_t n, std::mt19937& random) {
  std::string s;
  for (std::size_t k = 0; k < n; ++k) s += "ACGT"[random() % 4];
  return s;
}

void write_fasta(const fs::path& path, const std::string& sequence) {
  std::ofstream(path) << ">seq\n" << sequence << "\n";
}

TEST(CliDetails, HelpNamesTheProgram) {
  const auto top = run_cli("--help");
  EXPECT_EQ(top.status, 0);
  EXPECT_NE(top.out.find("Usage: seqtopo [OPTIONS] SUBCOMMAND"), std::string::npos) << top.out;
  const auto map = run_cli("map --help");
  EXPECT_NE(map.out.find("Usage: seqtopo map [OPTIONS]"), std::string::npos) << map.out;
  // --descriptor lists npy beside the image descriptors.
  std::istringstream lines(map.out);
  std::string line, descriptor;
  while (std::getline(lines, line)) {
    if (line.find("--descriptor") != std::string::npos) descriptor = line;
  }
  EXPECT_NE(descriptor.find("joint-histogram|patch|panorama|npy"), std::string::npos) << descriptor;
}

TEST(CliDetails, ParseErrorsPointToTheSubcommandsHelp) {
  for (const char* command : {"align", "map", "localize", "match-strings"}) {
    const auto r = run_cli(std::string(command) + " --no-such-option");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err_last_line().find(std::string("(see seqtopo ") + command + " --help)"), std::string::npos) << r.err;
  }
}

TEST(CliDetails, AlignReadsSoftMaskedFastaByLetter) {
  TempDir dir;
  std::mt19937 random(11);
  const std::string shared = random_dna(80, random);
  std::string masked = shared;
  for (auto& c : masked) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string a = random_dna(200, random) + shared + random_dna(200, random);
  const std::string b = random_dna(100, random) + masked + random_dna(150, random);  // soft-masked: lower case
  write_fasta(dir.path / "a.fa", a);
  write_fasta(dir.path / "b.fa", b);
  const std::string common = "align --a " + (dir.path / "a.fa").string() + " --b " + (dir.path / "b.fa").string() +
                             " --mismatch -2 --gap 3 --threshold 30 --json " + (dir.path / "out.json").string();
  auto r = run_cli(common);
  ASSERT_EQ(r.status, 0) << r.err;
  auto json = nlohmann::json::parse(read_file(dir.path / "out.json"));
  ASSERT_FALSE(json.at("alignments").empty());
  const auto& best = json.at("alignments").at(0);
  EXPECT_GE(best.at("score").get<double>(), 80.0);
  EXPECT_LE(best.at("a_begin").get<int>(), 200);
  EXPECT_GE(best.at("a_end").get<int>(), 280);
  EXPECT_LE(best.at("b_begin").get<int>(), 100);
  // Case-sensitive, the masked stretch matches nothing.
  r = run_cli(common + " --case-sensitive");
  ASSERT_EQ(r.status, 0) << r.err;
  json = nlohmann::json::parse(read_file(dir.path / "out.json"));
  EXPECT_TRUE(json.at("alignments").empty() || json.at("alignments").at(0).at("score").get<double>() < 40.0);

  // The view for reading: letters over letters, as in the files (lower case kept), a bar per equal pair.
  r = run_cli("align --a " + (dir.path / "a.fa").string() + " --b " + (dir.path / "b.fa").string() +
              " --mismatch -2 --gap 3 --threshold 30 --max-alignments 1 --text -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("{"), std::string::npos) << "the JSON goes to stdout only without --text -";
  EXPECT_NE(r.out.find("# 1  score"), std::string::npos) << r.out;
  std::string top, bottom, bars;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("A ", 0) == 0) top += line.substr(11, line.rfind("  ") - 11);
    if (line.rfind("B ", 0) == 0) bottom += line.substr(11, line.rfind("  ") - 11);
    if (line.rfind("   ", 0) == 0) bars += line;
  }
  EXPECT_NE(top.find(shared.substr(10, 60)), std::string::npos) << r.out;
  EXPECT_NE(bottom.find(masked.substr(10, 60)), std::string::npos) << r.out;
  EXPECT_GE(std::count(bars.begin(), bars.end(), '|'), 80);
}

TEST(CliDetails, AlignDefaultThresholdIsAboveChance) {
  TempDir dir;
  std::mt19937 random(5);
  write_fasta(dir.path / "a.fa", random_dna(400, random));
  write_fasta(dir.path / "b.fa", random_dna(400, random));
  const std::string args = "align --a " + (dir.path / "a.fa").string() + " --b " + (dir.path / "b.fa").string() +
                           " --json " + (dir.path / "out.json").string();
  // Threshold 0: the engine lists 100 chance alignments of two unrelated sequences.
  auto r = run_cli(args + " --threshold 0");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(dir.path / "out.json")).at("alignments").size(), 100U);
  // The default: above the best score against shuffled sequences; unrelated sequences give (almost) nothing.
  r = run_cli(args);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LE(nlohmann::json::parse(read_file(dir.path / "out.json")).at("alignments").size(), 2U);
  EXPECT_NE(r.err.find("auto: above chance"), std::string::npos) << r.err;
}

TEST(CliDetails, MatchStringsHeaderFirstAndGeometricRatesSayWhatTheyAreOver) {
  TempDir dir;
  // Two map points in two places; three test points, the third in place 1 but looking like place 0.
  std::ofstream(dir.path / "db.tsv") << "m0\tvAvBvCvD\t0\t0\t0\nm1\tvEvFvGvH\t10\t0\t1\n";
  std::ofstream(dir.path / "q.tsv") << "t0\tvAvBvCvD\t0.5\t0\t0\nt1\tvEvFvGvH\t10.5\t0\t1\nt2\tvAvBvCvD\t10\t1\t1\n";
  const auto out = dir.path / "out";
  const auto r = run_cli("match-strings --db " + (dir.path / "db.tsv").string() + " --queries " +
                         (dir.path / "q.tsv").string() + " --algorithm B --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string tsv = read_file(out / "matches.tsv");
  EXPECT_EQ(tsv.rfind("query_id\trank\tdb_id\tscore\n", 0), 0U) << tsv;
  const std::string table = read_file(out / "metrics.txt");
  EXPECT_NE(table.find("Top.  wrong     33.3 %   (of 3 test points)"), std::string::npos) << table;
  EXPECT_NE(table.find("(of 2 of the 3 test points: the topologically correct ones)"), std::string::npos) << table;
}

TEST(CliDetails, OnlineLatencyIsProcessingAndTheWaitIsApart) {
  TempDir dir;
  const fs::path corridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  fs::create_directories(dir.path / "map");
  for (int k = 1; k <= 40; ++k) {
    fs::create_symlink(corridor / (std::to_string(k) + ".jpg"), dir.path / "map" / (std::to_string(k) + ".jpg"));
  }
  // Three query frames, each sent once the answer to the one before has been read and 0.3 s have passed. Whatever
  // the machine's speed, by causality (one monotonic clock): a frame's latency (from its path read to its answer)
  // lies inside the window from sending the path to reading the answer, and the wait reported apart (from the
  // previous answer to the path read) covers at least the gap from reading that answer to sending the next path.
  // No threshold on how fast the machine is.
  const fs::path feeder = dir.write("feed.py", R"(import subprocess, sys, time
cli, map_dir, corridor, out = sys.argv[1:]
p = subprocess.Popen([cli, "localize", "--map", map_dir, "--query", "-", "--online", "--out", out],
                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
answered = None
for k in (41, 42, 43):
    if answered is not None:
        time.sleep(0.3)
    sent = time.monotonic()
    p.stdin.write(f"{corridor}/{k}.jpg\n")
    p.stdin.flush()
    line = p.stdout.readline()
    while line.startswith("query,"):
        line = p.stdout.readline()
    got = time.monotonic()
    gap = -1.0 if answered is None else 1e3 * (sent - answered)
    print(f"{line.strip()},{1e3 * (got - sent):.6f},{gap:.6f}")
    answered = got
p.stdin.close()
sys.exit(p.wait())
)");
  const auto r = run_command("python3 " + feeder.string() + " " + std::string(SEQTOPO_CLI) + " " +
                             (dir.path / "map").string() + " " + corridor.string() + " " + (dir.path / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::size_t q = 0;
  for (std::string line; std::getline(lines, line); ++q) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    ASSERT_EQ(fields.size(), 7U) << line;  // query,map,confidence,latency_ms,wait_ms + window, gap
    EXPECT_EQ(fields[0], std::to_string(q));
    const double latency = std::stod(fields[3]), wait = std::stod(fields[4]);
    const double window = std::stod(fields[5]), gap = std::stod(fields[6]);
    constexpr double rounding = 0.001;  // latency_ms and wait_ms have 3 decimals
    EXPECT_LE(latency, window + rounding) << "frame " << q << " counts more than its own processing";
    if (q > 0) {
      EXPECT_GE(gap, 300.0) << "frame " << q;
      EXPECT_GE(wait, gap - rounding) << "frame " << q << ": the wait for it is not reported apart";
    }
  }
  EXPECT_EQ(q, 3U) << r.out;
  const std::string csv = read_file(dir.path / "out" / "latency.csv");
  EXPECT_EQ(csv.rfind("query,latency_ms,wait_ms\n", 0), 0U) << csv;
}

// Issue 47, defect 5: joint histograms of a map and a query (or of sessions) of different image sizes were compared
// without a word: every query frame "not in the map". Inside one folder the same mix was already an error; now it
// is one everywhere, naming the input and both sizes (offline, --online, sessions, and map --online's folder).
TEST(CliDetails, JointHistogramsOfDifferentImageSizesAreRefusedEverywhere) {
  TempDir dir;
  std::mt19937 rng(3);
  for (const auto& [folder, width] : {std::pair{"small", 32}, std::pair{"large", 40}}) {
    fs::create_directories(dir.path / folder);
    for (int k = 0; k < 6; ++k) {
      seqtopo::RgbImage image(width, 24);
      for (auto& v : image.pixels) v = static_cast<std::uint8_t>(rng() % 256);
      seqtopo::plot::write_png(dir.path / folder / (std::to_string(k) + ".png"), image);
    }
  }
  const std::string small = (dir.path / "small").string(), large = (dir.path / "large").string();
  // The second input described is named: the query online and in a map of sessions, the map offline (the query's
  // frames are described first).
  const std::string large_named = large + ": its images are 40 x 24 pixels, those of " + small + " 32 x 24: the joint";
  const std::string small_named = small + ": its images are 32 x 24 pixels, those of " + large + " 40 x 24: the joint";
  for (const auto& [args, error] :
       {std::pair{"localize --map " + small + " --query " + large + " --descriptor joint-histogram", small_named},
        std::pair{"localize --map " + small + " --query " + large + " --descriptor joint-histogram --online",
                  large_named},
        std::pair{"map " + small + " " + large + " --descriptor joint-histogram", large_named}}) {
    SCOPED_TRACE(args);
    const auto r = run_cli(args + " --out " + (dir.path / "out").string());
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(r.err_last_line().rfind("seqtopo: error: " + error, 0), 0U) << r.err;
    EXPECT_FALSE(fs::exists(dir.path / "out"));
  }
  // map --online of a folder whose images change size (the offline map refuses it too)
  fs::copy_file(dir.path / "large" / "0.png", dir.path / "small" / "9.png");
  const auto r = run_cli("map " + small + " --online --out " + (dir.path / "out").string());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err_last_line().rfind("seqtopo: error: " + (dir.path / "small" / "9.png").string() +
                                        ": the image is 40 x 24 pixels, the first one 32 x 24",
                                    0),
            0U)
      << r.err;
}

// --every K was read for videos and bags only: an image folder and a descriptors.npy were mapped whole without a
// word. It keeps every K-th image (and odometry row) of a folder and every K-th row of an array: the same map as the
// thinned folder or array given whole. A similarity matrix is refused, not thinned.
TEST(CliDetails, EveryKeepsEveryKthImageOfAFolderAndRowOfAnArray) {
  TempDir dir;
  const fs::path corridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  fs::create_directories(dir.path / "half");
  std::ofstream all_odometry(dir.path / "odometry.csv"), half_odometry(dir.path / "half.csv");
  all_odometry << "index,x,y,theta\n";
  half_odometry << "index,x,y,theta\n";
  for (int k = 1; k <= 84; ++k) {
    all_odometry << k - 1 << "," << 0.3 * k << ",0,0\n";
    if ((k - 1) % 2 != 0) continue;
    fs::copy_file(corridor / (std::to_string(k) + ".jpg"), dir.path / "half" / (std::to_string(k) + ".jpg"));
    half_odometry << (k - 1) / 2 << "," << 0.3 * k << ",0,0\n";
  }
  all_odometry.close();
  half_odometry.close();
  const auto every = run_cli("map " + corridor.string() + " --every 2 --odometry " +
                             (dir.path / "odometry.csv").string() + " --out " + (dir.path / "every").string());
  ASSERT_EQ(every.status, 0) << every.err;
  const auto half = run_cli("map " + (dir.path / "half").string() + " --odometry " + (dir.path / "half.csv").string() +
                            " --out " + (dir.path / "whole").string());
  ASSERT_EQ(half.status, 0) << half.err;
  const auto map = nlohmann::json::parse(read_file(dir.path / "every" / "map.json"));
  EXPECT_EQ(map.at("labels").size(), 42U);
  for (const char* file : {"map.json", "alignments.json", "loop_closures.csv"}) {
    EXPECT_EQ(read_file(dir.path / "every" / file), read_file(dir.path / "whole" / file)) << file;
  }

  std::mt19937 random(3);
  std::normal_distribution<float> normal;
  seqtopo::DenseMatrix<float> rows(301, 16), kept(101, 16);
  for (std::size_t i = 0; i < rows.rows; ++i) {
    for (std::size_t d = 0; d < rows.cols; ++d) {
      rows(i, d) = normal(random) + (i >= 200 && i < 260 ? 3.0F * static_cast<float>((i - 150) % 7) : 0.0F);
      if (i % 3 == 0) kept(i / 3, d) = rows(i, d);
    }
  }
  seqtopo::io::write_npy(dir.path / "rows.npy", rows);
  seqtopo::io::write_npy(dir.path / "kept.npy", kept);
  const auto thinned =
      run_cli("map " + (dir.path / "rows.npy").string() + " --every 3 --out " + (dir.path / "r3").string());
  ASSERT_EQ(thinned.status, 0) << thinned.err;
  const auto given = run_cli("map " + (dir.path / "kept.npy").string() + " --out " + (dir.path / "k").string());
  ASSERT_EQ(given.status, 0) << given.err;
  EXPECT_EQ(read_file(dir.path / "r3" / "map.json"), read_file(dir.path / "k" / "map.json"));
  EXPECT_NE(thinned.err.find("101 images"), std::string::npos) << thinned.err;

  seqtopo::io::write_npy(dir.path / "similarity.npy", seqtopo::DenseMatrix<float>(20, 20, 0.5F));
  const auto refused =
      run_cli("map " + (dir.path / "similarity.npy").string() + " --every 2 --out " + (dir.path / "s").string());
  EXPECT_NE(refused.status, 0);
  EXPECT_EQ(refused.err.rfind("seqtopo: error: --every: ", 0), 0U) << refused.err;
}

}  // namespace

// The corridor with its second lap 40 % darker: the joint histogram's absolute bins see no revisit, so the default
// leaves it out of the fusion, says so naming it, and maps as the patch thumbnails alone do.
TEST(CliDetails, ADescriptorBlindToTheRevisitIsLeftOutOfTheFusion) {
  TempDir dir;
  const fs::path corridor = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
  fs::create_directories(dir.path / "dark");
  for (int k = 1; k <= 84; ++k) {
    seqtopo::RgbImage image = seqtopo::image::load_image(corridor / (std::to_string(k) + ".jpg"));
    if (k > 40) {
      for (auto& v : image.pixels) v = static_cast<std::uint8_t>(v * 0.6F);
    }
    char name[16];
    std::snprintf(name, sizeof name, "%02d.png", k);
    seqtopo::plot::write_png(dir.path / "dark" / name, image);
  }
  const std::string truth = " --ground-truth " + (corridor / "ground_truth.bmp").string();
  const auto fused = run_cli("map " + (dir.path / "dark").string() + truth + " --out " + (dir.path / "fused").string());
  ASSERT_EQ(fused.status, 0) << fused.err;
  EXPECT_NE(fused.err.find("(joint-histogram) sees no revisit"), std::string::npos) << fused.err;
  const auto alignments = nlohmann::json::parse(read_file(dir.path / "fused" / "alignments.json"));
  EXPECT_EQ(alignments["significance"]["blind_descriptors"], nlohmann::json::array({0}));
  const auto patch = run_cli("map " + (dir.path / "dark").string() + truth + " --descriptor patch --out " +
                             (dir.path / "patch").string());
  ASSERT_EQ(patch.status, 0) << patch.err;
  EXPECT_EQ(read_file(dir.path / "fused" / "loop_closures.csv"), read_file(dir.path / "patch" / "loop_closures.csv"));
  const auto metrics = nlohmann::json::parse(read_file(dir.path / "fused" / "metrics.json"));
  EXPECT_GT(metrics["loop_closure"]["f1"].get<double>(), 0.8);
}
