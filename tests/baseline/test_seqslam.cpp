// The SeqSLAM-style baseline against a direct brute-force evaluation of its definition.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::baseline {
namespace {

TEST(SeqSlam, FindsPlantedSequenceAtDifferentSpeed) {
  // The query (rows) drives the database route at 1.2x the speed: query q sees database 1.2 q + 5.
  const std::size_t nq = 40, nd = 80;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.0F, 0.5F);
  SimilarityMatrix s(nq, nd);
  for (auto& v : s.values) v = noise(rng);
  for (std::size_t q = 0; q < nq; ++q)
    s(q, static_cast<std::size_t>(std::lround(1.2 * static_cast<double>(q))) + 5) = 1.0F;
  SeqSlamConfig config;
  config.sequence_length = 8;
  config.min_velocity = 1.0F;
  config.max_velocity = 1.4F;
  const auto matches = seqslam_matches(s, config);
  for (std::size_t q = 10; q < nq; ++q) {
    ASSERT_TRUE(matches[q].valid);
    EXPECT_EQ(matches[q].match, static_cast<std::size_t>(std::lround(1.2 * static_cast<double>(q))) + 5) << q;
  }
}

TEST(SeqSlam, EqualsBruteForceDefinition) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0F, 1.0F);
  for (int round = 0; round < 20; ++round) {
    const std::size_t n = 15 + rng() % 60;  // several blocks of 16 columns, and a partial one
    SimilarityMatrix s(n, n);
    for (auto& v : s.values) v = u(rng);
    SeqSlamConfig config;
    config.self = true;
    config.min_separation = 3;
    config.sequence_length = 4;
    config.contrast_window = 0;
    config.velocity_steps = 3;
    const auto got = seqslam_matches(s, config);
    for (std::size_t q = 0; q < n; ++q) {
      bool valid = false;
      float best = 0;
      std::size_t best_j = 0;
      for (std::size_t j = 0; j + 3 <= q; ++j) {
        for (float v : {0.8F, 1.025F, 1.25F}) {
          double sum = 0;
          int count = 0;
          for (std::size_t k = 0; k < 4 && k <= q; ++k) {
            const double col = static_cast<double>(j) - static_cast<double>(v) * static_cast<double>(k);
            if (col < 0) break;
            sum += s(q - k, static_cast<std::size_t>(std::lround(col)));
            ++count;
          }
          const auto score = static_cast<float>(sum / count);
          if (!valid || score > best) {
            valid = true;
            best = score;
            best_j = j;
          }
        }
      }
      ASSERT_EQ(got[q].valid, valid) << q;
      if (valid) {
        EXPECT_EQ(got[q].match, best_j);
        EXPECT_EQ(got[q].score, best);  // the same sums in the same order
      }
    }
  }
}

// Self mode enhances only the part of each row its lines read: the matches are those on the whole enhanced matrix.
TEST(SeqSlam, SelfModeMatchesOnTheWholeEnhancedMatrix) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0F, 1.0F);
  for (int round = 0; round < 12; ++round) {
    const std::size_t n = 20 + rng() % 70;
    SimilarityMatrix s(n, n);
    for (auto& v : s.values) v = u(rng);
    SeqSlamConfig config;
    config.self = true;
    config.min_separation = 2 + static_cast<std::size_t>(round) * 3;  // below, at and above the sequence length
    config.sequence_length = 3 + static_cast<std::size_t>(round) % 8;
    config.contrast_window = 1 + static_cast<std::size_t>(round) % 6;
    const auto got = seqslam_matches(s, config);
    SeqSlamConfig on_enhanced = config;
    on_enhanced.contrast_window = 0;
    const auto expected = seqslam_matches(similarity::enhance_contrast(s, config.contrast_window), on_enhanced);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t q = 0; q < n; ++q) {
      ASSERT_EQ(got[q].valid, expected[q].valid) << round << ": " << q;
      EXPECT_EQ(got[q].match, expected[q].match) << round << ": " << q;
      EXPECT_EQ(got[q].score, expected[q].score) << round << ": " << q;
    }
  }
}

TEST(SeqSlam, EqualsBruteForceDefinitionAcrossSequencesWithHalfFrameSteps) {
  // Velocity 1.5 puts every other step exactly half way between two columns (rounded up, away from zero).
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1.0F, 1.0F);
  for (int round = 0; round < 20; ++round) {
    const std::size_t rows = 10 + rng() % 15, cols = 10 + rng() % 60;
    SimilarityMatrix s(rows, cols);
    for (auto& v : s.values) v = u(rng);
    SeqSlamConfig config;
    config.sequence_length = 6;
    config.contrast_window = 0;
    config.min_velocity = 0.5F;
    config.max_velocity = 1.5F;
    config.velocity_steps = 3;
    config.threads = 1 + round % 2;
    const auto got = seqslam_matches(s, config);
    for (std::size_t q = 0; q < rows; ++q) {
      float best = 0;
      std::size_t best_j = 0;
      bool valid = false;
      for (std::size_t j = 0; j < cols; ++j) {
        for (float v : {0.5F, 1.0F, 1.5F}) {
          double sum = 0;
          int count = 0;
          for (std::size_t k = 0; k < 6 && k <= q; ++k) {
            const double col = static_cast<double>(j) - static_cast<double>(v) * static_cast<double>(k);
            if (col < 0) break;
            sum += s(q - k, static_cast<std::size_t>(std::lround(col)));
            ++count;
          }
          const auto score = static_cast<float>(sum / count);
          if (!valid || score > best) valid = true, best = score, best_j = j;
        }
      }
      ASSERT_TRUE(got[q].valid);
      EXPECT_EQ(got[q].match, best_j) << round << " query " << q;
      EXPECT_EQ(got[q].score, best) << round << " query " << q;
    }
  }
}

}  // namespace
}  // namespace seqtopo::baseline
