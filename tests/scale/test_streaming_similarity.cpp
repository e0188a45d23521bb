// The streamed mapping score against the dense path: cosine matrix -> enhance_contrast_symmetric.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::scale {
namespace {

// A walk on the sphere that comes back over its first part (forward) and a later part (backward),
// so the self alignment has something to find.
std::vector<float> walk_descriptors(std::size_t n, std::size_t dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0F, 1.0F);
  std::vector<float> x(n * dim);
  for (std::size_t t = 0; t < dim; ++t) x[t] = noise(rng);
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t t = 0; t < dim; ++t) {
      float base = x[(i - 1) * dim + t];
      if (i >= n / 2 && i < n / 2 + n / 5) base = x[(i - n / 2) * dim + t];            // forward revisit
      if (i >= n / 2 + n / 5 && i < n / 2 + 2 * (n / 5)) base = x[(n - i) * dim + t];  // reverse revisit
      x[i * dim + t] = base + 0.4F * noise(rng);
    }
  }
  return x;
}

// The dense reference: float cosine of the normalised rows summed in dimension order, then the map's
// contrast enhancement from the similarity library.
SimilarityMatrix dense_scores(const StreamingSimilarity& s) {
  const auto x = s.normalized();
  const std::size_t n = s.size(), d = s.dim();
  SimilarityMatrix cosine(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      float dot = 0;
      for (std::size_t t = 0; t < d; ++t) dot += x[i * d + t] * x[j * d + t];
      cosine(i, j) = dot;
    }
  }
  return similarity::enhance_contrast_symmetric(cosine, s.config().contrast_window, s.config().contrast_offset);
}

TEST(StreamingSimilarity, NormalisesDescriptors) {
  const auto x = walk_descriptors(50, 7, 3);
  const StreamingSimilarity s(x, 50, 7);
  for (std::size_t i = 0; i < 50; ++i) {
    double norm2 = 0, dot = 0, nx = 0;
    for (std::size_t t = 0; t < 7; ++t) {
      norm2 += static_cast<double>(s.normalized()[i * 7 + t]) * s.normalized()[i * 7 + t];
      dot += static_cast<double>(s.normalized()[i * 7 + t]) * x[i * 7 + t];
      nx += static_cast<double>(x[i * 7 + t]) * x[i * 7 + t];
    }
    EXPECT_NEAR(norm2, 1.0, 1e-6);
    EXPECT_NEAR(dot, std::sqrt(nx), 1e-5 * std::sqrt(nx));  // same direction
  }
}

TEST(StreamingSimilarity, EqualsDenseContrastEnhancementBitForBit) {
  struct Case {
    std::size_t n, dim, window, tile;
    float offset;
  };
  const Case cases[] = {
      {1, 3, 10, 4, 0.5F},
      {17, 5, 3, 4, 0.0F},
      {120, 16, 10, 32, 0.5F},
      {203, 9, 4, 7, 0.25F},
      {150, 32, 0, 64, 0.5F},
      {90, 12, 60, 256, 1.0F},
      {700, 64, 10, 256, 0.5F},  // the defaults, interior tiles
      // Running sums (windows of 32 and more): tiles on and off the restarts, windows wider than the row.
      {400, 8, 40, 64, 0.5F},
      {333, 6, 100, 37, 0.5F},
      {260, 10, 32, 100, 0.0F},
      {70, 5, 200, 16, 0.5F}};
  for (const Case& c : cases) {
    const auto x = walk_descriptors(c.n, c.dim, static_cast<unsigned>(c.n + c.tile));
    const StreamingSimilarity s(x, c.n, c.dim, {c.window, c.offset, c.tile, 3});
    const SimilarityMatrix expected = dense_scores(s);
    std::mt19937 rng(7);
    for (std::size_t i = 0; i < c.n; ++i) {
      // Whole rows, and a random segment.
      std::vector<float> row(c.n);
      s.read_row(i, 0, c.n, row.data());
      for (std::size_t j = 0; j < c.n; ++j) ASSERT_EQ(row[j], expected(i, j)) << c.n << " " << i << "," << j;
      const std::size_t b = std::uniform_int_distribution<std::size_t>(0, c.n)(rng);
      const std::size_t e = std::uniform_int_distribution<std::size_t>(b, c.n)(rng);
      std::vector<float> seg(e - b);
      s.read_row(i, b, e, seg.data());
      for (std::size_t j = b; j < e; ++j) ASSERT_EQ(seg[j - b], expected(i, j));
      const std::size_t j = std::uniform_int_distribution<std::size_t>(0, c.n - 1)(rng);
      ASSERT_EQ(s.score(i, j), expected(i, j));
    }
  }
}

TEST(StreamingSimilarity, SameValuesFromConcurrentReadersWithATinyCache) {
  const std::size_t n = 180, dim = 10;
  const auto x = walk_descriptors(n, dim, 11);
  const StreamingSimilarity s(x, n, dim, {5, 0.5F, 16, 2});  // 2 tiles cached: constant eviction
  const SimilarityMatrix expected = dense_scores(s);
  std::vector<std::vector<float>> got(4, std::vector<float>(n * n));
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = t % 2 == 0 ? k : n - 1 - k;  // two forward and two backward readers
        s.read_row(i, 0, n, got[t].data() + i * n);
      }
    });
  }
  for (auto& th : threads) th.join();
  for (std::size_t t = 0; t < 4; ++t) EXPECT_EQ(got[t], expected.values) << "reader " << t;
  EXPECT_GT(s.stats().tiles_computed, (n / 16 + 1) * (n / 16 + 1));  // evictions recomputed tiles
}

TEST(StreamingSimilarity, SelfAlignmentsEqualTheDensePath) {
  const std::size_t n = 240, dim = 24;
  const auto x = walk_descriptors(n, dim, 5);
  const StreamingSimilarity s(x, n, dim, {10, 0.5F, 64, 0});
  const SimilarityMatrix dense = dense_scores(s);
  align::AlignConfig config;
  config.gap_a = config.gap_b = 1.5F;
  config.cap = 40.0F;
  config.threshold = 8.0F;
  config.self = true;
  config.min_separation = 10;
  const auto expected = align::local_alignments_both(align::ScoreSource::dense(dense.values, n, n), config);
  const auto got = align::local_alignments_both(s.source(), config);
  ASSERT_FALSE(expected.empty());  // the planted revisits are found
  EXPECT_EQ(got, expected);
}

// A zero descriptor (a uniform image's patch) stays zero: cosine 0 with every frame, itself included, in the tiles
// as cell by cell.
TEST(StreamingSimilarity, AZeroDescriptorHasCosineZeroWithEveryFrame) {
  auto x = walk_descriptors(40, 5, 7);
  for (std::size_t t = 0; t < 5; ++t) x[17 * 5 + t] = 0.0F;
  StreamingConfig config;
  config.tile = 8;
  const StreamingSimilarity s(x, 40, 5, config);
  const auto source = s.source();
  std::vector<float> row(40);
  for (std::size_t j = 0; j < 40; ++j) EXPECT_EQ(s.cosine(17, j), 0.0F) << j;
  for (std::size_t i = 0; i < 40; ++i) {
    source.read_row(i, 0, 40, row.data());
    for (std::size_t j = 0; j < 40; ++j) {
      ASSERT_TRUE(std::isfinite(row[j])) << i << ", " << j;
      EXPECT_EQ(row[j], s.score(i, j)) << i << ", " << j;
    }
  }
}

TEST(StreamingSimilarity, RejectsBadInput) {
  const std::vector<float> x(10, 1.0F);
  EXPECT_THROW(StreamingSimilarity(x, 3, 3), std::invalid_argument);
  EXPECT_THROW(StreamingSimilarity(x, 10, 0), std::invalid_argument);
  std::vector<float> infinite(10, 1.0F);
  infinite[4] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(StreamingSimilarity(infinite, 10, 1), std::invalid_argument);
  StreamingConfig bad;
  bad.tile = 0;
  EXPECT_THROW(StreamingSimilarity(x, 5, 2, bad), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::scale
