// The fast alignment engine against the scalar engine, parasail and EMBOSS matcher, all timed in one run
// on the same two random protein-like sequences (docs/engine.md has the table this prints).
//   build/release/bench/bench_engine [size = 10000] [threads = 0 (all cores)] [seed = 1]
// Gap convention: a linear gap G is parasail's open G / extend G, and matcher's -gapopen G -gapextend G
// (matcher charges open + extend * (L - 1); see tests/align/test_against_matcher.cpp).
#include <parasail.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/align/letter_problem.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace {

namespace fs = std::filesystem;
using namespace seqtopo;

constexpr const char* kAlphabet = align::LetterProblem::alphabet;
constexpr std::size_t kLetters = align::LetterProblem::letters;
constexpr int kGap = 4;

// CPU seconds of this process and of the children it waited for: on a shared machine wall time
// measures the other users as much as the code.
double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  rusage children{};
  getrusage(RUSAGE_CHILDREN, &children);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9 +
         static_cast<double>(children.ru_utime.tv_sec + children.ru_stime.tv_sec) +
         static_cast<double>(children.ru_utime.tv_usec + children.ru_stime.tv_usec) * 1e-6;
}

// The best of `repeats` runs (the first also pays for page faults).
template <typename F>
double seconds(F&& f, int repeats = 1) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = cpu_now();
    f();
    best = std::min(best, cpu_now() - t0);
  }
  return best;
}

template <typename F>
double wall_seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// matcher's top-`count` scores ("# Score:" lines of its pair output).
std::vector<int> matcher_scores(const fs::path& dir, int count) {
  const std::string cmd = "cd " + dir.string() +
                          " && matcher -asequence a.fa -bsequence b.fa -datafile ./MATRIX -gapopen " +
                          std::to_string(kGap) + " -gapextend " + std::to_string(kGap) + " -alternatives " +
                          std::to_string(count) + " -aformat3 pair -outfile stdout 2>/dev/null";
  std::vector<int> out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  char line[4096];
  while (std::fgets(line, sizeof line, pipe)) {
    if (std::string(line).rfind("# Score:", 0) == 0) out.push_back(std::atoi(line + 8));
  }
  pclose(pipe);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::stoul(argv[1]) : 10000;
  unsigned threads = argc > 2 ? static_cast<unsigned>(std::stoul(argv[2])) : 0;
  if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
  const unsigned seed = argc > 3 ? static_cast<unsigned>(std::stoul(argv[3])) : 1;

  const align::LetterProblem problem = align::random_letter_problem(n, seed);
  const auto& [a, b, a_text, b_text, matrix] = problem;
  parasail_matrix_t* pmatrix = parasail_matrix_create(kAlphabet, 5, -1);
  for (std::size_t x = 0; x < kLetters; ++x) {
    for (std::size_t y = 0; y < kLetters; ++y) {
      parasail_matrix_set_value(pmatrix, static_cast<int>(x), static_cast<int>(y), problem.score(x, y));
    }
  }
  const double cells = static_cast<double>(n) * static_cast<double>(n);

  align::AlignConfig config;
  config.gap_a = config.gap_b = kGap;
  const align::LetterScores letters{a, b, matrix, kLetters};
  float fill_score = 0;
  const double fill_one = seconds(
      [&] {
        fill_score = align::fast_best_score(letters, config, {1.0F, 1, align::Isa::best});
      },
      3);
  const double fill_all = wall_seconds([&] {
    align::fast_best_score(letters, config, {1.0F, threads, align::Isa::best});
  });
  // The same fill at scale 16: cells beyond 255 steps from the first rows on, so int16 lanes throughout.
  const double fill_int16 = seconds([&] { align::fast_best_score(letters, config, {16.0F, 1, align::Isa::best}); }, 3);
  auto top = config;
  top.max_alignments = 10;
  std::vector<align::LocalAlignment> ours;
  const double top10 = seconds([&] { ours = align::fast_local_alignments(letters, top, {1.0F, 1, align::Isa::best}); });

  const std::size_t small = std::min<std::size_t>(n, 3000);
  const align::LetterScores small_letters{std::span(a).first(small), std::span(b).first(small), matrix, kLetters};
  const double scalar = seconds([&] { align::local_alignments(small_letters.source(), top); });
  const double scalar_cells = static_cast<double>(small) * static_cast<double>(small);
  double scalar_fast_same = seconds([&] {
    align::fast_local_alignments(small_letters, top, {1.0F, 1, align::Isa::best});
  });

  int scan_score = 0;
  const double scan = seconds(
      [&] {
        parasail_result_t* r = parasail_sw_scan_16(a_text.data(), static_cast<int>(n), b_text.data(),
                                                   static_cast<int>(n), kGap, kGap, pmatrix);
        scan_score = parasail_result_get_score(r);
        parasail_result_free(r);
      },
      3);
  auto parasail_fill = [&](auto function) {
    return seconds(
        [&] {
          parasail_result_free(
              function(a_text.data(), static_cast<int>(n), b_text.data(), static_cast<int>(n), kGap, kGap, pmatrix));
        },
        3);
  };
  const double striped16 = parasail_fill(parasail_sw_striped_16);
  const double striped_sat = parasail_fill(parasail_sw_striped_sat);  // 8-bit, 16-bit if that saturates
  const double trace = seconds([&] {
    parasail_result_t* r = parasail_sw_trace_scan_16(a_text.data(), static_cast<int>(n), b_text.data(),
                                                     static_cast<int>(n), kGap, kGap, pmatrix);
    parasail_result_free(r);
  });
  parasail_matrix_free(pmatrix);

  // matcher: the same sequences and matrix through files
  const fs::path dir = fs::temp_directory_path() / ("seqtopo-bench-engine-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream m(dir / "MATRIX");
    m << " ";
    for (std::size_t x = 0; x < kLetters; ++x) m << "  " << kAlphabet[x];
    m << "\n";
    for (std::size_t x = 0; x < kLetters; ++x) {
      m << kAlphabet[x];
      for (std::size_t y = 0; y < kLetters; ++y) m << ' ' << static_cast<int>(matrix[x * kLetters + y]);
      m << "\n";
    }
    std::ofstream(dir / "a.fa") << ">a\n" << a_text << "\n";
    std::ofstream(dir / "b.fa") << ">b\n" << b_text << "\n";
  }
  std::vector<int> theirs;
  const double matcher = seconds([&] { theirs = matcher_scores(dir, 10); });
  fs::remove_all(dir);
  std::size_t same_scores = 0;
  for (std::size_t k = 0; k < std::min(ours.size(), theirs.size()); ++k)
    same_scores += ours[k].score == static_cast<float>(theirs[k]);

  std::printf("bench_engine: %zu x %zu, %u thread(s), isa %s, gap %d\n", n, n, threads,
              std::string(align::to_string(align::best_isa())).c_str(), kGap);
  std::printf("  %-48s %10s %8s\n", "what (CPU seconds unless marked wall)", "seconds", "GCUPS");
  auto line = [](const char* what, double s, double c) {
    std::printf("  %-48s %10.4f %8.2f\n", what, s, c / s * 1e-9);
  };
  line("fast: score-only fill, 1 thread", fill_one, cells);
  line("fast: score-only fill, 1 thread, int16 (scale 16)", fill_int16, cells);
  line("fast: score-only fill, all threads (wall)", fill_all, cells);
  line("fast: top-10 alignments, 1 thread", top10, cells);
  line("scalar engine: top-10 on the 3000 x 3000 prefix", scalar, scalar_cells);
  line("fast: top-10 on the 3000 x 3000 prefix, 1 thread", scalar_fast_same, scalar_cells);
  line("parasail sw_scan_16", scan, cells);
  line("parasail sw_striped_16", striped16, cells);
  line("parasail sw_striped_sat (8-bit, else 16)", striped_sat, cells);
  line("parasail sw_trace_scan_16", trace, cells);
  line("EMBOSS matcher: top-10 alignments", matcher, cells);
  const double per_core = cells / fill_one * 1e-9;
  const double speedup = scalar / scalar_cells / (fill_one / cells);
  std::printf(
      "targets: %.2f GCUPS/core (>= 8: %s); %.1fx scalar kernel (>= 20: %s); fill / parasail scan %.2f (<= 1.5: %s); "
      "matcher / top-10 %.1fx (>= 10: %s)\n",
      per_core, per_core >= 8 ? "met" : "NOT met", speedup, speedup >= 20 ? "met" : "NOT met", fill_one / scan,
      fill_one / scan <= 1.5 ? "met" : "NOT met", matcher / top10, matcher / top10 >= 10 ? "met" : "NOT met");
  std::printf(
      "vs parasail's striped kernels: fill / sw_striped_16 %.2f, int16 fill / sw_striped_16 %.2f, fill / "
      "sw_striped_sat %.2f\n",
      fill_one / striped16, fill_int16 / striped16, fill_one / striped_sat);
  std::printf("check: best score ours %g, parasail %d; top-10 scores equal to matcher's: %zu of %zu\n", fill_score,
              scan_score, same_scores, theirs.size());
  return fill_score == static_cast<float>(scan_score) ? 0 : 1;
}
