// The alignment engine on random similarity-like matrices: cells per second of the full fill and the
// cost of finding all alignments (Waterman-Eggert with incremental recompute). Not run by the tests.
//   build/release/bench/bench_align --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <random>

#include "seqtopo/align/smith_waterman.hpp"

namespace {

// Background noise below zero with a few planted diagonal and anti-diagonal revisits.
std::vector<float> revisit_matrix(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(-0.6F, 0.5F);
  std::vector<float> s(n * n);
  for (auto& v : s) v = noise(rng);
  for (std::size_t r = 0; r < 4; ++r) {
    const std::size_t len = n / 8, i0 = n / 2 + r * n / 10, j0 = r * n / 9;
    for (std::size_t k = 0; k < len && i0 + k < n; ++k) {
      s[(i0 + k) * n + (r % 2 ? j0 + len - k : j0 + k)] = 1.0F;
    }
  }
  return s;
}

void BM_BestAlignment(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto s = revisit_matrix(n, 1);
  seqtopo::align::AlignConfig config;
  config.max_alignments = 1;
  config.cap = 40.0F;
  for (auto _ : state) {
    benchmark::DoNotOptimize(seqtopo::align::local_alignments(seqtopo::align::ScoreSource::dense(s, n, n), config));
  }
  state.counters["cells/s"] =
      benchmark::Counter(static_cast<double>(n * n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_AllAlignmentsAboveThreshold(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto s = revisit_matrix(n, 2);
  seqtopo::align::AlignConfig config;
  config.threshold = 5.0F;
  config.cap = 40.0F;
  std::size_t found = 0;
  for (auto _ : state) {
    const auto all = seqtopo::align::local_alignments_both(seqtopo::align::ScoreSource::dense(s, n, n), config, 2);
    found = all.size();
    benchmark::DoNotOptimize(all);
  }
  state.counters["alignments"] = static_cast<double>(found);
  state.counters["cells/s"] =
      benchmark::Counter(static_cast<double>(2 * n * n), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_BestAlignment)->Arg(500)->Arg(2000)->Arg(4000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllAlignmentsAboveThreshold)->Arg(500)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
