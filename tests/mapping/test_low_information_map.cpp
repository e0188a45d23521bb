// MapConfig::mask_low_information: frames of little information (a tunnel's dark frames: alike one another,
// whatever the place) carry no evidence of a revisit. Synthetic sequences of known truth: a route of textured
// frames (AR(1) descriptors), dark stretches of nearly one descriptor each with a faint drifting light, with and
// without a revisit around them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "common/sanitizers.hpp"
#include "seqtopo/mapping/map_builder.hpp"

namespace seqtopo::mapping {
namespace {

constexpr std::size_t kDim = 32;

using Descriptors = std::vector<std::vector<float>>;

// `length` places of a route: smooth random descriptors (each the last one drifted), from `seed`.
Descriptors route(std::size_t length, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, 1.0F);
  Descriptors out;
  std::vector<float> x(kDim);
  for (auto& v : x) v = g(rng);
  for (std::size_t k = 0; k < length; ++k) {
    for (auto& v : x) v = 0.6F * v + 0.8F * g(rng);
    out.push_back(x);
  }
  return out;
}

// The same places seen again: each descriptor with noise.
Descriptors seen_again(const Descriptors& places, unsigned seed, float noise) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, noise);
  Descriptors out = places;
  for (auto& d : out) {
    for (auto& v : d) v += g(rng);
  }
  return out;
}

// A dark stretch: nearly the same descriptor everywhere, a faint light drifting across two of its components.
Descriptors dark(std::size_t length, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, 0.05F);
  Descriptors out;
  for (std::size_t k = 0; k < length; ++k) {
    std::vector<float> d(kDim, 0.0F);
    d[0] = 3.0F;
    d[1] = 0.3F * std::sin(0.3F * static_cast<float>(k));
    d[2] = 0.3F * std::cos(0.2F * static_cast<float>(k));
    for (auto& v : d) v += g(rng);
    out.push_back(d);
  }
  return out;
}

SimilarityMatrix similarity(const Descriptors& d) {
  const std::size_t n = d.size();
  SimilarityMatrix s(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      double dist = 0;
      for (std::size_t k = 0; k < kDim; ++k) dist += std::abs(d[i][k] - d[j][k]);
      s(i, j) = static_cast<float>(1.0 - dist / kDim);
    }
  }
  return s;
}

void append(Descriptors& to, const Descriptors& from) { to.insert(to.end(), from.begin(), from.end()); }

std::vector<std::size_t> range(std::size_t begin, std::size_t end) {
  std::vector<std::size_t> out;
  for (std::size_t k = begin; k < end; ++k) out.push_back(k);
  return out;
}

// One pass of 400 places with a corridor of identical doors at 150-269 (a 6-place door pattern passed 20 times, with
// noise), no revisit.
Descriptors door_corridor(unsigned seed) {
  Descriptors pass = route(400, seed);
  const Descriptors door = route(6, seed + 1000);
  std::mt19937 rng(seed + 2000);
  std::normal_distribution<float> g(0.0F, 0.6F);
  for (std::size_t i = 150; i < 270; ++i) {
    for (std::size_t k = 0; k < kDim; ++k) pass[i][k] = 0.8F * door[(i - 150) % 6][k] + g(rng);
  }
  return pass;
}

// One pass, no revisit, with two dark stretches far apart: dark matched with dark is not a revisit.
TEST(LowInformationMap, DarkStretchesOfOnePassAreNoRevisit) {
  std::size_t with_mask = 0, without_mask = 0;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Descriptors places = route(300, seed);
    Descriptors pass(places.begin(), places.begin() + 100);
    append(pass, dark(40, seed + 10));
    pass.insert(pass.end(), places.begin() + 100, places.begin() + 200);
    append(pass, dark(40, seed + 20));
    pass.insert(pass.end(), places.begin() + 200, places.end());
    std::vector<std::size_t> masked = range(100, 140);
    for (std::size_t k : range(240, 280)) masked.push_back(k);
    const SimilarityMatrix s = similarity(pass);
    without_mask += build_map(std::vector<SimilarityMatrix>{s}, MapConfig{}).pruning.pairs.size();
    const MapResult r = build_map(std::vector<SimilarityMatrix>{s}, MapConfig{}, {}, masked);
    with_mask += r.pruning.pairs.size();
    EXPECT_EQ(r.decisions.low_information_frames, masked);
  }
  EXPECT_GT(without_mask, 20U) << "the dark stretches must look like a revisit without the mask";
  EXPECT_EQ(with_mask, 0U);
}

// A corridor of identical doors in one pass (a 6-place door pattern passed 20 times, with noise), no revisit: the
// stretch matches itself at every multiple of its period far beyond chance, and the map finds no revisit in it
// once its frames are masked as a tandem repeat (significance/tandem_repeats.hpp). 50 seeds: at most the chance
// alignments any sequence has at E <= 0.01 (about one run in a hundred).
TEST(LowInformationMap, ACorridorOfIdenticalDoorsIsNoRevisit) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("50 sequences of 400 frames");
  std::size_t masked_runs = 0, unmasked_runs = 0;
  const std::size_t seeds = 50;
  for (unsigned seed = 1; seed <= seeds; ++seed) {
    const Descriptors pass = door_corridor(seed);
    const SimilarityMatrix s = similarity(pass);
    const MapResult r = build_map(std::vector<SimilarityMatrix>{s}, MapConfig{});
    masked_runs += r.pruning.pairs.empty() ? 0 : 1;
    MapConfig off;
    off.mask_low_information = false;
    unmasked_runs += build_map(std::vector<SimilarityMatrix>{s}, off).pruning.pairs.empty() ? 0 : 1;
  }
  EXPECT_GE(unmasked_runs * 10, seeds * 9) << "the doors must look like a revisit without the mask";
  EXPECT_LE(masked_runs, seeds / 25);
}

// The same corridor through the engine the streamed similarities take (build_map_from_enhanced reading the scores
// through a function, as `--streaming` and `--sparse` give them): the repeat is found from those scores and masked
// there too, with the same frames and the same map as the dense path.
TEST(LowInformationMap, ACorridorOfIdenticalDoorsIsNoRevisitForStreamedScores) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("10 sequences of 400 frames, each mapped three times");
  std::size_t masked_runs = 0, unmasked_runs = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const Descriptors pass = door_corridor(seed);
    const std::vector<SimilarityMatrix> s{similarity(pass)};
    MapConfig config;
    config.frames_per_place = 1.0;
    const MapResult dense = build_map(s, config);
    const SimilarityMatrix enhanced = enhanced_scores(s, settings_in_frames(config, 1.0).score.contrast_window);
    const auto streamed_source = align::ScoreSource::function(
        enhanced.rows, enhanced.cols, [&enhanced](std::size_t i, std::size_t j) { return enhanced(i, j); });
    const MapResult streamed = build_map_from_enhanced(streamed_source, config);
    EXPECT_GT(streamed.decisions.tandem_repeat_frames, 50U) << seed;
    EXPECT_EQ(streamed.decisions.low_information_frames, dense.decisions.low_information_frames) << seed;
    EXPECT_EQ(streamed.pruning.pairs.size(), dense.pruning.pairs.size()) << seed;
    masked_runs += streamed.pruning.pairs.empty() ? 0 : 1;
    MapConfig off = config;
    off.mask_low_information = false;
    unmasked_runs += build_map_from_enhanced(streamed_source, off).pruning.pairs.empty() ? 0 : 1;
  }
  EXPECT_GE(unmasked_runs, 9U) << "the doors must look like a revisit without the mask";
  EXPECT_LE(masked_runs, 1U);
}

// A route driven twice through the same tunnel: the revisit on either side of it is one revisit, the tunnel's
// own pairs lie on the line between the evidence around it, and the map keeps (nearly) every closure the same
// route without a tunnel has.
TEST(LowInformationMap, ARevisitThroughATunnelStaysOneRevisit) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Descriptors places = route(150, seed);
    const Descriptors again = seen_again(places, seed + 100, 0.5F);
    // Sequence: pass 1 (places 0-149, the tunnel at 60-89), 40 places elsewhere, pass 2 (the same).
    const Descriptors elsewhere = route(40, seed + 200);
    Descriptors clean = places, tunnel;
    append(clean, elsewhere);
    append(clean, again);
    const std::size_t second = 190;
    tunnel = clean;
    const Descriptors dark1 = dark(30, seed + 300), dark2 = dark(30, seed + 400);
    for (std::size_t k = 0; k < 30; ++k) tunnel[60 + k] = dark1[k], tunnel[second + 60 + k] = dark2[k];
    std::vector<std::size_t> masked = range(60, 90);
    for (std::size_t k : range(second + 60, second + 90)) masked.push_back(k);

    const MapResult base = build_map(std::vector<SimilarityMatrix>{similarity(clean)}, MapConfig{});
    const MapResult r = build_map(std::vector<SimilarityMatrix>{similarity(tunnel)}, MapConfig{}, {}, masked);
    std::set<std::size_t> closed_base, closed;
    for (const auto& p : base.pruning.pairs) {
      if (p.i < second + 60 || p.i >= second + 90) closed_base.insert(p.i);
    }
    ASSERT_GT(closed_base.size(), 100U) << "the clean route must be mapped";
    std::size_t kept = 0;
    for (const auto& p : r.pruning.pairs) {
      EXPECT_EQ(p.i, p.j + second) << "every closure on the revisit, inside the tunnel too (seed " << seed << ")";
      closed.insert(p.i);
    }
    for (std::size_t i : closed_base) kept += closed.count(i);
    EXPECT_GE(kept * 10, closed_base.size() * 9) << "seed " << seed;
    // One alignment through the tunnel, not two on either side of it.
    std::size_t spanning = 0;
    for (const auto& a : r.alignments) spanning += a.a_begin < second + 60 && a.a_end > second + 90 ? 1 : 0;
    EXPECT_GE(spanning, 1U) << "seed " << seed;
  }
}

// The lights out in one pass only: a dark stretch inserted in each pass at a different place (the other pass has no
// frames there), a route of 150 places driven twice, the stretches 12 and 14 places from its ends. The alignment leaves
// the masked frames out, so a stretch is a free step for the pass that has it: the revisit on either side of each is
// one revisit, not pieces too short to be significant (where a gap across the stretch would have cost its whole
// evidence), and no dark frame is a closure.
TEST(LowInformationMap, ARevisitWithTheLightsOutInOnePassStaysOneRevisit) {
  constexpr std::size_t kDark = 50, cut1 = 12, cut2 = 136;  // pass 1 dark after place cut1, pass 2 after cut2
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Descriptors places = route(150, seed);
    const Descriptors again = seen_again(places, seed + 100, 0.5F);
    const Descriptors elsewhere = route(40, seed + 200);
    // Clean: pass 1, 40 places elsewhere, pass 2 (its first frame `second`).
    const std::size_t second = 190;
    Descriptors clean = places;
    append(clean, elsewhere);
    append(clean, again);
    // The same with the dark stretches; clean_frame[k]: frame k's frame in the clean sequence (kNone: dark).
    Descriptors lights_out;
    std::vector<std::size_t> clean_frame, masked;
    const auto add = [&](const Descriptors& d, std::size_t from) {
      for (std::size_t k = 0; k < d.size(); ++k) lights_out.push_back(d[k]), clean_frame.push_back(from + k);
    };
    const auto add_dark = [&](unsigned dark_seed) {
      for (const auto& d : dark(kDark, dark_seed)) {
        masked.push_back(lights_out.size());
        lights_out.push_back(d), clean_frame.push_back(kNone);
      }
    };
    add(Descriptors(places.begin(), places.begin() + cut1), 0);
    add_dark(seed + 300);
    add(Descriptors(places.begin() + cut1, places.end()), cut1);
    add(elsewhere, 150);
    add(Descriptors(again.begin(), again.begin() + cut2), second);
    add_dark(seed + 400);
    add(Descriptors(again.begin() + cut2, again.end()), second + cut2);

    const MapResult base = build_map(std::vector<SimilarityMatrix>{similarity(clean)}, MapConfig{});
    const MapResult r = build_map(std::vector<SimilarityMatrix>{similarity(lights_out)}, MapConfig{}, {}, masked);
    EXPECT_EQ(r.decisions.low_information_frames, masked);
    std::set<std::size_t> closed_base, closed;
    for (const auto& p : base.pruning.pairs) closed_base.insert(p.i);
    ASSERT_GT(closed_base.size(), 120U) << "the clean route must be mapped";
    for (const auto& p : r.pruning.pairs) {
      ASSERT_NE(clean_frame[p.i], kNone) << "a dark frame closed (seed " << seed << ")";
      ASSERT_NE(clean_frame[p.j], kNone) << "a dark frame closed (seed " << seed << ")";
      const auto place_i = static_cast<long>(clean_frame[p.i]) - static_cast<long>(second);
      EXPECT_LE(std::abs(place_i - static_cast<long>(clean_frame[p.j])), 2L) << "seed " << seed;
      closed.insert(clean_frame[p.i]);
    }
    std::size_t kept = 0;
    for (std::size_t i : closed_base) kept += closed.count(i);
    EXPECT_GE(kept * 10, closed_base.size() * 9) << "seed " << seed;
    // Pass 2's first cut1 places and its last 150 - cut2 are each cut off by a dark stretch from the rest: one
    // alignment spans both.
    const std::size_t pass2 = 150 + kDark + 40;  // pass 2's first frame in the dark sequence
    std::size_t spanning = 0;
    for (const auto& a : r.alignments) spanning += a.a_begin < pass2 + cut1 && a.a_end > pass2 + cut2 + kDark ? 1 : 0;
    EXPECT_GE(spanning, 1U) << "seed " << seed;
  }
}

TEST(LowInformationMap, MaskedFramesOutOfRangeAreRefused) {
  const SimilarityMatrix s = similarity(route(50, 1));
  const std::vector<std::size_t> bad = {3, 50};
  EXPECT_THROW(build_map(std::vector<SimilarityMatrix>{s}, MapConfig{}, {}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::mapping
