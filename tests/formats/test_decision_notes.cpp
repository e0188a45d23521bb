// The notes of a map's decisions: each fact said once, in the run's order, with the numbers it holds; a descriptor
// left out named when the names are given, and a real map's blind descriptor said so.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "seqtopo/formats/decision_notes.hpp"

namespace seqtopo::formats {
namespace {

bool says(const std::vector<std::string>& notes, const std::string& text) {
  for (const auto& n : notes) {
    if (n.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(DecisionNotes, EachFactIsOneLineInTheRunsOrder) {
  mapping::MapDecisions d;
  EXPECT_TRUE(decision_notes(d).empty());
  d.place_scale_missing = true;
  d.similarities = 3;
  d.blind_descriptors = {0, 2};
  d.low_information_frames = {4, 5, 6, 20};
  d.linear_phase.push_back({0.5F, true, -0.05, -0.1, 0, 0.75F});
  d.linear_phase.push_back({0.75F, false, 0, -0.1, 12.5, std::nullopt});
  d.unfitted_chance_alignments = 7;
  d.score_threshold = 20;
  d.trimmed_chance_end_pairs = 3;
  d.trimmed_odometry_pairs = 2;
  d.tandem_repeat_frames = 3;  // of the 4 masked frames
  const std::vector<std::string> names{"joint-histogram", "patch", "signature"};
  const auto notes = decision_notes(d, names);
  ASSERT_EQ(notes.size(), 10U);
  EXPECT_EQ(notes[0].rfind("no place scale", 0), 0U);
  EXPECT_EQ(notes[1].rfind("descriptor 1 of 3 (joint-histogram) sees no revisit", 0), 0U) << notes[1];
  EXPECT_EQ(notes[2].rfind("descriptor 3 of 3 (signature) sees no revisit", 0), 0U) << notes[2];
  EXPECT_EQ(
      notes[3].rfind("4 frames of little information (dark or near-uniform; 3 of them in tandem repeats, below) in "
                     "2 stretches",
                     0),
      0U)
      << notes[3];
  EXPECT_EQ(notes[4],
            "contrast offset 0.50: the scores' global alignment rate is -0.050 a step, above -0.10 (linear phase); "
            "raised to 0.75");
  EXPECT_EQ(notes[5],
            "chance alignments stay long (12.5 places) even at contrast offset 0.75: revisits may be "
            "overestimated");
  EXPECT_EQ(notes[6],
            "too few chance alignments (7) to fit the significance statistics: a fixed threshold of 20 and "
            "cap none apply");
  EXPECT_EQ(notes[7].rfind("3 aligned pairs at alignments' ends", 0), 0U);
  EXPECT_EQ(notes[8].rfind("odometry: 2 aligned pairs", 0), 0U);
  EXPECT_EQ(notes[9].rfind("3 frames in tandem repeats", 0), 0U);
  d.tandem_repeat_frames = 0;  // dark frames alone
  EXPECT_EQ(decision_notes(d)[3].rfind("4 frames of little information (dark or near-uniform) in 2 stretches", 0), 0U);
  // Unnamed: by number alone.
  EXPECT_TRUE(says(decision_notes(d), "descriptor 3 of 3 sees no revisit"));
}

// A map of two descriptors, one of them noise: its note names the noise, in either order.
// Stretches of masked frames against a brute force: a frame starts a stretch when the one before it is not masked,
// ends one when the one after it is not.
TEST(DecisionNotes, FrameStretchesAreTheRunsOfConsecutiveFrames) {
  EXPECT_TRUE(seqtopo::formats::frame_stretches({}).empty());
  std::mt19937 rng(4);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<bool> masked(40);
    for (std::size_t f = 0; f < masked.size(); ++f) masked[f] = rng() % 3 == 0;
    std::vector<std::size_t> sorted;
    std::vector<std::pair<std::size_t, std::size_t>> want;
    for (std::size_t f = 0; f < masked.size(); ++f) {
      if (!masked[f]) continue;
      sorted.push_back(f);
      if (f == 0 || !masked[f - 1]) want.emplace_back(f, f);
      if (f + 1 == masked.size() || !masked[f + 1]) want.back().second = f;
    }
    EXPECT_EQ(seqtopo::formats::frame_stretches(sorted), want) << trial;
  }
}

TEST(DecisionNotes, ABlindDescriptorOfARealMapIsNamed) {
  const auto descriptor = [](unsigned seed, float strength) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0F, 1.0F);
    SimilarityMatrix s(240, 240, 0.0F);
    for (auto& v : s.values) v = noise(rng);
    for (std::size_t k = 0; k < 40; ++k) s(100 + k, 10 + k) += strength, s(239 - k, 40 + k) += strength;
    for (std::size_t i = 0; i < 240; ++i) {
      for (std::size_t j = 0; j < i; ++j) s(j, i) = s(i, j);
    }
    return s;
  };
  const SimilarityMatrix sees = descriptor(1, 3.0F), blind = descriptor(2, 0.0F);
  const auto fused = mapping::build_map(std::vector<SimilarityMatrix>{sees, blind});
  EXPECT_TRUE(says(decision_notes(fused.decisions), "descriptor 2 of 2 sees no revisit"));
  const std::vector<std::string> names{"noise", "sees"};
  const auto reversed = mapping::build_map(std::vector<SimilarityMatrix>{blind, sees});
  EXPECT_TRUE(says(decision_notes(reversed.decisions, names), "descriptor 1 of 2 (noise) sees no revisit"));
}

}  // namespace
}  // namespace seqtopo::formats
