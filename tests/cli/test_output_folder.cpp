// Output folders are replaced as a set (issue #18, findings 3, 4 and 5): a reader sees the whole old result or
// the whole new one; a run that fails, is stopped (SIGINT, SIGTERM: exit 130, 143, its staging folder removed)
// or killed (SIGKILL) leaves the old set whole, and the next run removes what the killed one left; the folder
// holds exactly one run's files, listed in manifest.json. Faults in the folder swap come from a preloaded shim
// (fault_rename.cpp) that makes the rename(2) onto the folder fail or stall.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::read_file;
using seqtopo::test_support::run_cli;
using seqtopo::test_support::run_command;

// The files of a folder (relative path -> bytes).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[e.path().lexically_relative(dir).generic_string()] = read_file(e.path());
  }
  return files;
}

// Hidden leftovers beside (and inside) `out`: staging folders, old sets, lock and temporary files.
std::vector<std::string> leftovers(const fs::path& out) {
  std::vector<std::string> found;
  for (const auto& folder : {out.parent_path(), out}) {
    if (!fs::is_directory(folder)) continue;
    for (const auto& e : fs::directory_iterator(folder)) {
      const std::string name = e.path().filename().string();
      if (name.find("seqtopo-staging") != std::string::npos || name.find("seqtopo-old") != std::string::npos ||
          name.find("seqtopo-lock") != std::string::npos || name.find(".tmp.") != std::string::npos ||
          name.find(".staging") != std::string::npos) {
        found.push_back(e.path().string());
      }
    }
  }
  return found;
}

// A process started in the background, its stderr in a file.
struct Background {
  pid_t pid = -1;
  fs::path err;

  Background(const std::vector<std::string>& args, const fs::path& err_file,
             const std::vector<std::string>& env_extra = {})
      : err(err_file) {
    std::vector<std::string> words = {SEQTOPO_CLI};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_words;
    for (char** e = environ; *e != nullptr; ++e) env_words.emplace_back(*e);
    env_words.insert(env_words.end(), env_extra.begin(), env_extra.end());
    std::vector<char*> envp;
    for (auto& w : env_words) envp.push_back(w.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t defaults;
    sigemptyset(&defaults);
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&defaults, s);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    if (posix_spawn(&pid, words[0].c_str(), &files, &attr, argv.data(), envp.data()) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attr);
  }
  ~Background() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  // Waits for `ready` (polled every 5 ms, at most 60 s); false when the process ended first.
  template <typename Ready>
  bool wait_for(Ready ready) {
    for (int k = 0; k < 12000; ++k) {
      if (ready()) return true;
      int raw = 0;
      if (::waitpid(pid, &raw, WNOHANG) == pid) {
        pid = -1;
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  // The exit status (128 + signal when it was killed by one, as a shell reports it).
  int finish() {
    int raw = 0;
    ::waitpid(pid, &raw, 0);
    pid = -1;
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  }
};

class OutputFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    out_ = dir_.path / "out";
    // A small map (the old set) and a long one: 3,000 descriptors, a walk and its noisy repetition.
    small_ = write_walk("small.npy", 120);
    long_ = write_walk("long.npy", 3000);
  }

  std::string write_walk(const std::string& name, std::size_t n) {
    std::mt19937 rng(static_cast<unsigned>(n));
    std::normal_distribution<float> step(0.0F, 1.0F);
    const std::size_t dim = 32, half = n / 2;
    seqtopo::DenseMatrix<float> d(n, dim);
    for (std::size_t i = 0; i < half; ++i) {
      for (std::size_t k = 0; k < dim; ++k) d(i, k) = (i > 0 ? d(i - 1, k) : 0.0F) + step(rng);
    }
    for (std::size_t i = half; i < n; ++i) {
      for (std::size_t k = 0; k < dim; ++k) d(i, k) = d(i - half, k) + 0.3F * step(rng);
    }
    seqtopo::io::write_npy(dir_.path / name, d);
    return (dir_.path / name).string();
  }

  // The old set: a finished map of the small walk, checked against its own manifest.
  std::map<std::string, std::string> make_old_set() {
    const auto r = run_cli("map " + small_ + " --out " + out_.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(seqtopo::io::verify_manifest(out_), "");
    return snapshot(out_);
  }

  std::vector<std::string> long_map() const { return {"map", long_, "--threads", "1", "--out", out_.string()}; }

  bool staging_exists() const {
    for (const auto& e : fs::directory_iterator(dir_.path)) {
      if (e.path().filename().string().find("seqtopo-staging") != std::string::npos) return true;
    }
    return false;
  }

  // The fault library is preloaded (LD_PRELOAD), which AddressSanitizer's runtime does not allow before it:
  // the fault tests run in the Release build.
  static bool fault_injection_available() {
#if defined(__SANITIZE_ADDRESS__)
    return false;
#else
    return true;
#endif
  }
  std::vector<std::string> fault(const std::string& mode, int ms = 4000) const {
    std::string asan = "verify_asan_link_order=0";
    if (const char* a = std::getenv("ASAN_OPTIONS")) asan = std::string(a) + ":" + asan;
    return {"LD_PRELOAD=" SEQTOPO_FAULT_LIB,
            "SEQTOPO_FAULT_TARGET=" + fs::absolute(out_).lexically_normal().string(),
            "SEQTOPO_FAULT_MODE=" + mode,
            "SEQTOPO_FAULT_MARK=" + (dir_.path / "mark").string(),
            "SEQTOPO_FAULT_MS=" + std::to_string(ms),
            "ASAN_OPTIONS=" + asan};
  }

  std::string env_prefix(const std::vector<std::string>& env) const {
    std::string text = "env";
    for (const auto& e : env) text += " '" + e + "'";
    return text + " ";
  }

  // The next run after a failed or killed one: succeeds, and nothing is left beside the folder.
  void expect_next_run_cleans_up() {
    const auto r = run_cli("map " + small_ + " --out " + out_.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(leftovers(out_), std::vector<std::string>{});
    EXPECT_EQ(seqtopo::io::verify_manifest(out_), "");
  }

  const seqtopo::test_support::TempDir dir_;
  fs::path out_;
  std::string small_, long_;
};

// Finding 3: one rename failing left six files of the new run beside the old ones (exit 1).
TEST_F(OutputFolder, ARenameThatFailsLeavesTheOldSetWhole) {
  if (!fault_injection_available()) GTEST_SKIP() << "LD_PRELOAD fault library under AddressSanitizer";
  const auto old_set = make_old_set();
  const auto r =
      run_command(env_prefix(fault("fail")) + "'" + SEQTOPO_CLI + "' map " + long_ + " --out " + out_.string());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err_last_line().rfind("seqtopo: error: " + out_.string() + ": ", 0), 0U) << r.err;
  EXPECT_EQ(snapshot(out_), old_set);
  EXPECT_EQ(leftovers(out_), std::vector<std::string>{});
}

// Finding 3, the reproduction: `similarity.png` made a folder in an existing --out. It is not the old
// run's file: the run is refused before any work and the folder stays as it is.
TEST_F(OutputFolder, AFolderWhereTheOldSetHadAFileIsRefusedBeforeAnyWork) {
  const auto old_set = make_old_set();
  fs::remove(out_ / "similarity.png");
  fs::create_directory(out_ / "similarity.png");
  const auto before = snapshot(out_);
  const auto r = run_cli("map " + long_ + " --out " + out_.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.rfind("seqtopo: error: " + out_.string() + ": holds 'similarity.png/'", 0), 0U) << r.err;
  EXPECT_EQ(r.err.find("[1/4]"), std::string::npos) << "no work before the refusal: " << r.err;
  EXPECT_EQ(snapshot(out_), before);
  EXPECT_TRUE(fs::is_directory(out_ / "similarity.png"));
}

// Finding 3: killed during the renames, map.json was the new map while scores.npy and report.html were the old.
// Killed while the swap stalls, the folder is the whole old set; killed just after it, the whole new one.
TEST_F(OutputFolder, KilledDuringTheSwapTheFolderIsOneWholeSet) {
  if (!fault_injection_available()) GTEST_SKIP() << "LD_PRELOAD fault library under AddressSanitizer";
  const auto old_set = make_old_set();
  {
    Background run(long_map(), dir_.path / "err.txt", fault("before"));
    ASSERT_TRUE(run.wait_for([&] { return fs::exists(dir_.path / "mark"); })) << read_file(dir_.path / "err.txt");
    ::kill(run.pid, SIGKILL);
    EXPECT_EQ(run.finish(), 128 + SIGKILL);
  }
  EXPECT_EQ(snapshot(out_), old_set);
  EXPECT_FALSE(leftovers(out_).empty()) << "the killed run's full staging folder (removed by the next run)";
  expect_next_run_cleans_up();

  fs::remove(dir_.path / "mark");
  {
    Background run(long_map(), dir_.path / "err.txt", fault("after"));
    ASSERT_TRUE(run.wait_for([&] { return fs::exists(dir_.path / "mark"); })) << read_file(dir_.path / "err.txt");
    ::kill(run.pid, SIGKILL);
    EXPECT_EQ(run.finish(), 128 + SIGKILL);
  }
  EXPECT_EQ(seqtopo::io::verify_manifest(out_), "") << "the new set, whole";
  EXPECT_NE(snapshot(out_), old_set);
  EXPECT_EQ(seqtopo::io::read_manifest(out_).files.size(), old_set.size() - 1);
  expect_next_run_cleans_up();
}

// Finding 4: killed runs left `--out/.staging.tmp.<pid>.0/` after SIGKILL, SIGINT or SIGTERM, and no later run
// removed it. SIGINT and SIGTERM in the middle of a long map: exit 130 / 143, the staging folder removed, the
// old set whole. SIGKILL: the old set whole, and the next run removes the staging folder.
TEST_F(OutputFolder, StoppedOrKilledInTheMiddleOfALongMap) {
  const auto old_set = make_old_set();
  for (const int signal : {SIGINT, SIGTERM, SIGKILL}) {
    SCOPED_TRACE(strsignal(signal));
    Background run(long_map(), dir_.path / "err.txt");
    ASSERT_TRUE(run.wait_for([&] { return staging_exists(); })) << read_file(dir_.path / "err.txt");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // well into the similarity stage
    ::kill(run.pid, signal);
    EXPECT_EQ(run.finish(), 128 + signal) << read_file(dir_.path / "err.txt");
    EXPECT_EQ(snapshot(out_), old_set);
    if (signal == SIGKILL) {
      EXPECT_TRUE(staging_exists());
    } else {
      EXPECT_EQ(leftovers(out_), std::vector<std::string>{}) << "the stopped run removes its staging folder";
      EXPECT_EQ(read_file(dir_.path / "err.txt").find("error"), std::string::npos) << "a clean stop";
    }
  }
  expect_next_run_cleans_up();
}

// A stop signal while the swap is under way: the swap finishes (the new set, whole). Issue 47, defect 11: the
// process then exited 143 (130) with the new set installed, and a caller checking the status believed the old set
// was still there. Once the new set is in place the run ends as it would have: exit 0, the old set removed. Just
// after the swap, the same.
TEST_F(OutputFolder, StoppedDuringOrAfterTheSwapTheRunSucceeds) {
  if (!fault_injection_available()) GTEST_SKIP() << "LD_PRELOAD fault library under AddressSanitizer";
  for (const int signal : {SIGINT, SIGTERM}) {
    for (const char* mode : {"before", "after"}) {
      SCOPED_TRACE(std::string(strsignal(signal)) + " " + mode);
      make_old_set();
      fs::remove(dir_.path / "mark");
      Background run(long_map(), dir_.path / "err.txt", fault(mode, 1500));
      ASSERT_TRUE(run.wait_for([&] { return fs::exists(dir_.path / "mark"); })) << read_file(dir_.path / "err.txt");
      ::kill(run.pid, signal);
      EXPECT_EQ(run.finish(), 0) << read_file(dir_.path / "err.txt");
      EXPECT_EQ(seqtopo::io::verify_manifest(out_), "");
      EXPECT_EQ(seqtopo::io::read_manifest(out_).files.size(), 9U) << "the long map's set";
      EXPECT_EQ(leftovers(out_), std::vector<std::string>{});
    }
  }
}

// Issue 47, defect 10: two runs writing one --out at once both exited 0 and both said "wrote 9 files"; only one
// set remained. The second is refused (exit 1, naming the folder and the first's process) before any work; the
// first finishes and its set is the folder's.
TEST_F(OutputFolder, TwoRunsWritingOneFolderAtOnce) {
  make_old_set();
  Background first(long_map(), dir_.path / "err.txt");
  ASSERT_TRUE(first.wait_for([&] { return staging_exists(); })) << read_file(dir_.path / "err.txt");
  const auto second = run_cli("map " + small_ + " --out " + out_.string());
  EXPECT_EQ(second.status, 1) << second.err;
  EXPECT_EQ(second.err_last_line().rfind("seqtopo: error: " + out_.string() +
                                             ": is being written by another seqtopo run (process " +
                                             std::to_string(first.pid) + ")",
                                         0),
            0U)
      << second.err;
  EXPECT_EQ(second.err.find("[1/"), std::string::npos) << "no work before the refusal: " << second.err;
  EXPECT_EQ(first.finish(), 0) << read_file(dir_.path / "err.txt");
  EXPECT_EQ(seqtopo::io::verify_manifest(out_), "");
  EXPECT_EQ(seqtopo::io::read_manifest(out_).files.size(), 9U) << "the first (long) run's set";
  EXPECT_EQ(leftovers(out_), std::vector<std::string>{});
}

// Issue 47, defect 13: map.json edited by the user was replaced without a word. Refused before any work, naming
// the folder and the file; the folder stays as it is.
TEST_F(OutputFolder, AnEditedFileOfTheOldSetIsRefused) {
  make_old_set();
  std::string map = read_file(out_ / "map.json");
  map[map.size() / 2] = map[map.size() / 2] == ' ' ? '\t' : ' ';
  std::ofstream(out_ / "map.json", std::ios::binary) << map;
  const auto before = snapshot(out_);
  const auto r = run_cli("map " + small_ + " --out " + out_.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.rfind("seqtopo: error: " + out_.string() +
                            ": holds 'map.json', changed since the seqtopo run that wrote it (its SHA-256",
                        0),
            0U)
      << r.err;
  EXPECT_EQ(snapshot(out_), before);
  EXPECT_EQ(leftovers(out_), std::vector<std::string>{});
}

// Finding 5: metric_map.png of a run with --odometry stayed next to a later run's unrelated map.json.
TEST_F(OutputFolder, FilesOfEarlierRunsDoNotStay) {
  std::string odometry = "index,x,y,theta\n";
  for (int k = 0; k < 120; ++k) odometry += std::to_string(k) + "," + std::to_string(k % 60) + ",0,0\n";
  const auto odo = dir_.write("odometry.csv", odometry);
  auto r = run_cli("map " + small_ + " --odometry " + odo.string() + " --out " + out_.string());
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_TRUE(fs::exists(out_ / "metric_map.png"));
  r = run_cli("map " + long_ + " --out " + out_.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(out_ / "metric_map.png")) << "a stale file of the earlier run";
  EXPECT_EQ(seqtopo::io::verify_manifest(out_), "");
  std::set<std::string> listed{"manifest.json"};
  for (const auto& f : seqtopo::io::read_manifest(out_).files) listed.insert(f.name);
  std::set<std::string> present;
  for (const auto& [name, bytes] : snapshot(out_)) present.insert(name);
  EXPECT_EQ(present, listed) << "exactly one run's files";
}

// Finding 5: with --out set to the input folder the next run read the output similarity.png as a frame. An
// output folder is never an input folder, inside one, or around one.
TEST_F(OutputFolder, InputFoldersAreNeverOutputFolders) {
  const fs::path frames = dir_.path / "frames";
  fs::create_directories(frames);
  for (const auto& e : fs::directory_iterator(fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor")) {
    if (e.path().extension() == ".jpg") fs::copy_file(e.path(), frames / e.path().filename());
  }
  const auto before = snapshot(frames);
  for (const auto& out : {frames, frames / "out", dir_.path}) {
    SCOPED_TRACE(out.string());
    const auto r = run_cli("map " + frames.string() + " --out " + out.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err.rfind("seqtopo: error: " + out.string() + ": ", 0), 0U) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_EQ(snapshot(frames), before);
  EXPECT_FALSE(fs::exists(frames / "out"));
  EXPECT_EQ(leftovers(frames / "out"), std::vector<std::string>{});
  // the other inputs too: odometry, ground truth
  std::string rows = "index,x,y\n";
  for (int k = 0; k < 120; ++k) rows += std::to_string(k) + "," + std::to_string(k % 60) + ",0\n";
  const auto poses = dir_.write("poses.csv", rows);
  const auto r = run_cli("map " + small_ + " --ground-truth " + poses.string() + " --gt-radius 1 --out " +
                         (dir_.path / "empty").string());
  EXPECT_EQ(r.status, 0) << r.err;
  const auto inside =
      run_cli("map " + small_ + " --ground-truth " + poses.string() + " --gt-radius 1 --out " + dir_.path.string());
  EXPECT_EQ(inside.status, 1) << inside.err;
}

// A folder the user filled is not replaced: not empty without a manifest, or holding files its manifest does
// not list.
TEST_F(OutputFolder, FoldersWithOtherFilesAreRefused) {
  fs::create_directories(out_);
  dir_.write("out/notes.txt", "mine");
  auto r = run_cli("map " + small_ + " --out " + out_.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no manifest.json"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(out_ / "notes.txt"), "mine");
  fs::remove(out_ / "notes.txt");
  make_old_set();
  dir_.write("out/notes.txt", "mine");
  r = run_cli("map " + small_ + " --out " + out_.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("holds 'notes.txt'"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(out_ / "notes.txt"), "mine");
  dir_.write("file", "x");
  r = run_cli("map " + small_ + " --out " + (dir_.path / "file").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("not a folder"), std::string::npos) << r.err;
}

// Every command that writes a folder gets the guarantee: a manifest of exactly its files, the folder replaced.
TEST_F(OutputFolder, EveryCommandThatWritesAFolder) {
  seqtopo::DenseMatrix<float> qm(30, 40, 0.0F);
  for (std::size_t q = 0; q < 30; ++q) qm(q, q + 5) = 1.0F;
  seqtopo::io::write_npy(dir_.path / "qm.npy", qm);
  const auto db = dir_.write("db.tsv", "a\tvAB\t0\t0\t0\nb\tvCD\t1\t0\t1\n");
  const auto queries = dir_.write("q.tsv", "x\tvAB\t0\t0\t0\n");
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"map", "map " + small_},
      {"localize", "localize --input-kind similarity --map " + (dir_.path / "qm.npy").string()},
      {"similarity", "similarity " + small_},
      {"match-strings", "match-strings --db " + db.string() + " --queries " + queries.string()},
      {"simulate",
       "simulate --scenario figure-eight --no-images --max-frames 20 --panorama-width 64 "
       "--panorama-height 8 --supersample 1"},
      {"bench scale --write-route", "bench scale --sizes 200 --dim 8"},
  };
  for (std::size_t k = 0; k < commands.size(); ++k) {
    const auto& [name, command] = commands[k];
    SCOPED_TRACE(name);
    const fs::path out = dir_.path / ("out-" + std::to_string(k));
    // an earlier set with a file this command never writes
    seqtopo::io::OutputDirectory earlier(out);
    earlier.write("stale-file-of-an-earlier-run.txt", "old");
    earlier.commit();
    const auto r =
        run_cli(command + (name == "bench scale --write-route" ? " --write-route " : " --out ") + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_FALSE(fs::exists(out / "stale-file-of-an-earlier-run.txt"));
    EXPECT_EQ(seqtopo::io::verify_manifest(out), "");
    EXPECT_EQ(seqtopo::io::read_manifest(out).command, "seqtopo " + name);
    EXPECT_EQ(leftovers(out), std::vector<std::string>{});
  }
}

}  // namespace
