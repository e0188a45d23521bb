// seqtopo bench align: speed of the fast alignment engine against the scalar engine, on two random protein-like
// sequences (docs/engine.md). One run measures everything on the same input. The comparison with parasail is
// bench/bench_engine.cpp (parasail is a benchmark dependency, not linked into seqtopo).
#include <fmt/format.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/align/letter_problem.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo::cli::bench_align_command {
namespace {

constexpr std::size_t kLetters = align::LetterProblem::letters;
constexpr int kGap = 2;  // linear gap [score units]

struct BenchAlignOptions {
  std::size_t size = 10000;
  unsigned threads = 0;
  unsigned seed = 1;
  bool json = false;
};

double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}
double wall_now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// The best of `repeats` runs, in CPU seconds of the process (single-threaded work: on a shared machine
// wall time measures the other users as much as the code) or in wall seconds (multi-threaded work).
template <typename F>
double seconds(F&& f, int repeats = 1, bool wall = false) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = wall ? wall_now() : cpu_now();
    f();
    best = std::min(best, (wall ? wall_now() : cpu_now()) - t0);
  }
  return best;
}

void run(const BenchAlignOptions& o) {
  if (o.size == 0) throw InputError("--size", "must be > 0");
  const unsigned threads = resolve_threads(o.threads);
  const align::LetterProblem problem = align::random_letter_problem(o.size, o.seed);
  const auto& [a, b, a_text, b_text, matrix] = problem;
  align::AlignConfig config;
  config.gap_a = config.gap_b = kGap;
  const align::LetterScores letters{a, b, matrix, kLetters};
  const double cells = static_cast<double>(o.size) * static_cast<double>(o.size);
  const int repeats = o.size <= 20000 ? 3 : 1;

  // our score-only fill, one core and all of them
  float best_one = 0, best_all = 0;
  const double fill_one = seconds(
      [&] {
        best_one = align::fast_best_score(letters, config, {1.0F, 1, align::Isa::best});
      },
      repeats);
  const double fill_all = seconds(
      [&] {
        best_all = align::fast_best_score(letters, config, {1.0F, threads, align::Isa::best});
      },
      repeats, true);
  // our full run: the ten best non-intersecting alignments
  auto top = config;
  top.max_alignments = 10;
  std::vector<align::LocalAlignment> found;
  const double all_alignments = seconds([&] {
    found = align::fast_local_alignments(letters, top, {1.0F, 1, align::Isa::best});
  });

  // the scalar engine, on a smaller square if needed, scaled by cells (its table takes 5 bytes per cell)
  const std::size_t scalar_size = std::min<std::size_t>(o.size, 3000);
  const align::LetterScores small{std::span(a).first(scalar_size), std::span(b).first(scalar_size), matrix, kLetters};
  auto one = config;
  one.max_alignments = 1;
  const double scalar_cells = static_cast<double>(scalar_size) * static_cast<double>(scalar_size);
  float scalar_best = 0;
  const double scalar_seconds = seconds([&] {
    const auto r = align::local_alignments(small.source(), one);
    scalar_best = r.empty() ? 0.0F : r.front().score;
  });
  const float fast_small = align::fast_best_score(small, config, {1.0F, 1, align::Isa::best});

  const double scalar_per_cell = scalar_seconds / scalar_cells;
  nlohmann::json j;
  j["size"] = o.size;
  j["seed"] = o.seed;
  j["threads"] = threads;
  j["isa"] = std::string(align::to_string(align::best_isa()));
  j["cells"] = cells;
  j["fill_seconds_1_thread"] = fill_one;
  j["fill_seconds_wall"] = fill_all;
  j["top10_seconds"] = all_alignments;
  j["scalar_seconds"] = scalar_seconds;
  j["scalar_cells"] = scalar_cells;
  j["gcups_per_core"] = cells / fill_one * 1e-9;
  j["gcups_wall"] = cells / fill_all * 1e-9;
  j["seconds_are"] = "CPU seconds of the process, except fill_seconds_wall";
  j["speedup_vs_scalar"] = scalar_per_cell * cells / fill_one;
  j["best_score"] = best_one;
  j["scores_agree"] =
      best_one == best_all && fast_small == scalar_best && (found.empty() || found.front().score == best_one);
  j["alignments_found"] = found.size();
  if (o.json) {
    std::cout << j.dump(1) << "\n";
    return;
  }
  std::cout << fmt::format("seqtopo bench align: {} x {} letters, {} thread(s), {}\n", o.size, o.size, threads,
                           j["isa"].get<std::string>());
  std::cout << fmt::format("  {:<44} {:>10} {:>10}\n", "what (CPU seconds unless marked wall)", "seconds", "GCUPS");
  auto line = [&](const std::string& what, double s, double c) {
    std::cout << fmt::format("  {:<44} {:>10.4f} {:>10.2f}\n", what, s, c / s * 1e-9);
  };
  line("fast engine, score-only fill, 1 thread", fill_one, cells);
  line(fmt::format("fast engine, score-only fill, {} threads (wall)", threads), fill_all, cells);
  line("fast engine, top-10 alignments, 1 thread", all_alignments, cells);
  line(fmt::format("scalar engine, best alignment ({0} x {0})", scalar_size), scalar_seconds, scalar_cells);
  std::cout << fmt::format("  speedup vs scalar {:.1f}x, scores agree: {} (parasail: bench/bench_engine)\n",
                           j["speedup_vs_scalar"].get<double>(), j["scores_agree"].get<bool>() ? "yes" : "NO");
}

const RegisterBenchCommand registered{
    {"align", "Speed of the fast alignment engine against the scalar engine on random sequences", [](CLI::App& app) {
       auto o = std::make_shared<BenchAlignOptions>();
       add_number(app, "--size", o->size, {.min = 1, .max = 1e6}, "Length of each sequence");
       add_number(app, "--threads", o->threads, kThreads, "Worker threads (0 = all cores)");
       add_number(app, "--seed", o->seed, kNonNegative, "Seed of the random sequences and matrix");
       app.add_flag("--json", o->json, "Print one JSON object instead of a table");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::bench_align_command
