#include "seqtopo/scale/sparse_candidates.hpp"

#include <faiss/IndexFlat.h>
#include <faiss/IndexIVFFlat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "seqtopo/core/stopwatch.hpp"

namespace seqtopo::scale {
namespace {}  // namespace

std::vector<std::vector<std::uint32_t>> nearest_neighbours(std::span<const float> descriptors, std::size_t n,
                                                           std::size_t dim, const CandidateConfig& config,
                                                           CandidateStats* stats) {
  if (dim == 0 || descriptors.size() != n * dim) {
    throw std::invalid_argument("nearest neighbours: descriptors have " + std::to_string(descriptors.size()) +
                                " values, expected " + std::to_string(n) + " x " + std::to_string(dim));
  }
  if (config.exclude == 0) throw std::invalid_argument("nearest neighbours: exclude must be >= 1 (the frame itself)");
  std::vector<std::vector<std::uint32_t>> out(n);
  if (n == 0 || config.neighbours == 0) return out;
  CandidateStats local;
  auto t0 = std::chrono::steady_clock::now();
  const auto d = static_cast<faiss::Index::idx_t>(dim);
  const auto count = static_cast<faiss::Index::idx_t>(n);
  std::unique_ptr<faiss::IndexFlatIP> quantizer;
  std::unique_ptr<faiss::Index> index;
  std::size_t lists =
      config.lists != 0 ? config.lists : static_cast<std::size_t>(2.0 * std::sqrt(static_cast<double>(n)));
  lists = std::min(lists, n / 39);
  if (config.exact || lists < 2) {
    index = std::make_unique<faiss::IndexFlatIP>(d);
  } else {
    quantizer = std::make_unique<faiss::IndexFlatIP>(d);
    auto ivf = std::make_unique<faiss::IndexIVFFlat>(quantizer.get(), d, lists, faiss::METRIC_INNER_PRODUCT);
    ivf->cp.seed = config.seed;
    ivf->cp.verbose = false;
    // Coarse cells only route the search (distances inside the lists are exact): a short k-means on
    // 32 points per cell is enough.
    ivf->cp.niter = 8;
    ivf->cp.max_points_per_centroid = 32;
    ivf->cp.min_points_per_centroid = 1;
    ivf->nprobe = std::min(config.probes, lists);
    ivf->train(count, descriptors.data());
    index = std::move(ivf);
  }
  index->add(count, descriptors.data());
  local.seconds_index = seconds_since(t0);

  // The frame itself and its 2 (exclude - 1) temporal neighbours come first; ask for enough to skip them.
  const std::size_t want = std::min(n, config.neighbours + 2 * config.exclude - 1);
  t0 = std::chrono::steady_clock::now();
  const std::size_t batch = 16384;
  std::vector<float> dist(batch * want);
  std::vector<faiss::Index::idx_t> labels(batch * want);
  for (std::size_t q0 = 0; q0 < n; q0 += batch) {
    const std::size_t q = std::min(batch, n - q0);
    index->search(static_cast<faiss::Index::idx_t>(q), descriptors.data() + q0 * dim,
                  static_cast<faiss::Index::idx_t>(want), dist.data(), labels.data());
    for (std::size_t a = 0; a < q; ++a) {
      const std::size_t i = q0 + a;
      auto& row = out[i];
      for (std::size_t k = 0; k < want && row.size() < config.neighbours; ++k) {
        const faiss::Index::idx_t l = labels[a * want + k];
        if (l < 0) continue;  // fewer than `want` found in the probed lists
        const auto j = static_cast<std::size_t>(l);
        if ((i > j ? i - j : j - i) < config.exclude) continue;
        row.push_back(static_cast<std::uint32_t>(j));
      }
    }
  }
  local.seconds_search = seconds_since(t0);
  if (stats != nullptr) {
    stats->seconds_index = local.seconds_index;
    stats->seconds_search = local.seconds_search;
  }
  return out;
}

SparseScores sparse_map_scores(const StreamingSimilarity& similarity, float background, const CandidateConfig& config,
                               CandidateStats* stats) {
  CandidateStats local;
  const auto neighbours =
      nearest_neighbours(similarity.normalized(), similarity.size(), similarity.dim(), config, &local);
  const auto t0 = std::chrono::steady_clock::now();
  // Unordered pairs (i > j), each scored once: the score is symmetric bit for bit.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  const auto n = static_cast<long>(neighbours.size());
  const auto reach = static_cast<long>(config.diagonal_reach);
  auto add = [&](long a, long b) {
    if (a < 0 || b < 0 || a >= n || b >= n) return;
    const long hi = std::max(a, b), lo = std::min(a, b);
    if (static_cast<std::size_t>(hi - lo) < config.exclude) return;
    pairs.emplace_back(static_cast<std::uint32_t>(hi), static_cast<std::uint32_t>(lo));
  };
  for (std::size_t i = 0; i < neighbours.size(); ++i) {
    for (const std::uint32_t j : neighbours[i]) {
      const auto a = static_cast<long>(i), b = static_cast<long>(j);
      add(a, b);
      for (long t = 1; t <= reach; ++t) {
        add(a + t, b + t);
        add(a - t, b - t);
        add(a + t, b - t);
        add(a - t, b + t);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<float> values(pairs.size());
#pragma omp parallel for schedule(dynamic, 4096)
  for (long k = 0; k < static_cast<long>(pairs.size()); ++k) {
    const auto& [i, j] = pairs[static_cast<std::size_t>(k)];
    values[static_cast<std::size_t>(k)] = similarity.score(i, j);
  }
  std::vector<SparseEntry> entries;
  entries.reserve(2 * pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    entries.push_back({pairs[k].first, pairs[k].second, values[k]});
    entries.push_back({pairs[k].second, pairs[k].first, values[k]});
  }
  local.pairs = entries.size();
  local.seconds_scores = seconds_since(t0);
  if (stats != nullptr) *stats = local;
  return SparseScores(similarity.size(), similarity.size(), background, std::move(entries));
}

}  // namespace seqtopo::scale
