// Recall of the sparse mode against the exact (dense) alignment on Nordland summer + winter
// (3,600 frames, the second half revisits the first). Both align the same score: cosine of SeqSLAM's
// patch-normalised thumbnails, contrast-enhanced as the map does (window 10, offset 0.5), with the
// map's alignment settings. The dense path reads every cell (streamed); the sparse path keeps the
// score at the k nearest neighbours of each frame and a constant background elsewhere.
//
//   bench_sparse_nordland [NORDLAND_DIR] [EXACT_LOOP_CLOSURES_CSV]
// NORDLAND_DIR defaults to ../shared/data/nordland-64x32; the optional CSV is `seqtopo map`'s
// loop_closures.csv on the same 3,600 frames, compared too.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/image/patch_thumbnail.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_candidates.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"

namespace {

using namespace seqtopo;
constexpr std::size_t kSeason = 1800;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<evaluation::ScoredPair> pairs_of(const std::vector<align::LocalAlignment>& alignments) {
  std::vector<evaluation::ScoredPair> out;
  for (const auto& a : alignments) {
    for (const auto& [i, j] : a.pairs) out.push_back({std::max(i, j), std::min(i, j), a.score});
  }
  return out;
}

bool same_place(std::size_t i, std::size_t j) {
  const long d = static_cast<long>(i % kSeason) - static_cast<long>(j % kSeason);
  return std::abs(d) <= 2;
}

// Images whose best pair is a true loop closure.
std::set<std::size_t> true_detections(const std::vector<evaluation::ScoredPair>& pairs) {
  std::set<std::size_t> out;
  for (const auto& p : evaluation::best_pair_per_image(pairs)) {
    if (same_place(p.i, p.j)) out.insert(p.i);
  }
  return out;
}

void report(const char* name, const std::vector<evaluation::ScoredPair>& pairs, const std::set<std::size_t>& reference,
            double seconds) {
  const auto m = evaluation::evaluate_loop_closures(pairs, 2 * kSeason, same_place, 10);
  const auto found = true_detections(pairs);
  std::size_t both = 0;
  for (const std::size_t i : reference) both += found.count(i);
  std::printf("| %s | %.3f | %.3f | %.3f | %zu | %.3f | %.2f |\n", name, m.precision, m.recall, m.f1, found.size(),
              reference.empty() ? 0.0 : static_cast<double>(both) / static_cast<double>(reference.size()), seconds);
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : "../shared/data/nordland-64x32";
  std::vector<float> descriptors;
  std::size_t dim = 0;
  for (const char* season : {"summer", "winter"}) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir / season)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.size() != kSeason) {
      std::fprintf(stderr, "%s/%s: expected %zu images, found %zu\n", dir.c_str(), season, kSeason, files.size());
      return 1;
    }
    for (const auto& f : files) {
      const auto d = image::patch_thumbnail(image::load_image(f));
      dim = d.size();
      descriptors.insert(descriptors.end(), d.begin(), d.end());
    }
  }
  const std::size_t n = 2 * kSeason;
  // A constant patch becomes all zeros; give such a frame a tiny constant direction instead.
  for (std::size_t i = 0; i < n; ++i) {
    bool zero = true;
    for (std::size_t t = 0; t < dim; ++t) zero = zero && descriptors[i * dim + t] == 0.0F;
    if (zero) descriptors[i * dim] = 1e-6F;
  }
  const scale::StreamingSimilarity sim(descriptors, n, dim);
  align::AlignConfig config;
  config.gap_a = config.gap_b = 1.5F;
  config.cap = 40.0F;
  config.threshold = 8.0F;
  config.self = true;
  config.min_separation = 10;

  auto t0 = std::chrono::steady_clock::now();
  const auto dense = align::local_alignments_both(sim.source(), config);
  const double dense_seconds = seconds_since(t0);
  const auto dense_pairs = pairs_of(dense);
  const auto reference = true_detections(dense_pairs);

  std::printf("| mode | precision | recall | F1 | loop closures (true) | found by both / by exact | seconds |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  report("exact (dense, every pair)", dense_pairs, reference, dense_seconds);
  const float background = -0.5F;
  for (const std::size_t reach : {0U, 5U}) {
    for (const std::size_t k : {10U, 20U}) {
      scale::CandidateConfig cc;
      cc.neighbours = k;
      cc.exclude = 10;
      cc.diagonal_reach = reach;
      t0 = std::chrono::steady_clock::now();
      const auto scores = scale::sparse_map_scores(sim, background, cc);
      const auto sparse = scale::sparse_local_alignments_both(scores, config);
      const double seconds = seconds_since(t0);
      char name[96];
      std::snprintf(name, sizeof name, "sparse, k = %zu, diagonal reach %zu, background %.1f", k, reach,
                    static_cast<double>(background));
      report(name, pairs_of(sparse), reference, seconds);
    }
  }
  if (argc > 2) {
    // `seqtopo map`'s retained pairs (its default fused preset, with pruning): i,j,score per line.
    std::ifstream csv(argv[2]);
    std::string line;
    std::vector<evaluation::ScoredPair> map_pairs;
    while (std::getline(csv, line)) {
      std::istringstream in(line);
      std::size_t i = 0, j = 0;
      float s = 0;
      char c1 = 0, c2 = 0;
      if (in >> i >> c1 >> j >> c2 >> s) map_pairs.push_back({std::max(i, j), std::min(i, j), s});
    }
    report("`seqtopo map` (fused preset, pruned)", map_pairs, reference, 0.0);
  }
  return 0;
}
