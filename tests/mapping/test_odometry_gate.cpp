// The odometry gate: alignments that odometry contradicts are dropped, revisits are kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/mapping/odometry_gate.hpp"

namespace seqtopo::mapping {
namespace {

// A 20 m corridor walked east and back west at 0.5 m per image (81 images, 0..40 out, 40..80 back),
// with odometry that drifts sideways by 2 cm per metre.
std::vector<Pose2> out_and_back() {
  std::vector<Pose2> poses;
  for (int k = 0; k <= 80; ++k) {
    const double along = k <= 40 ? 0.5 * k : 0.5 * (80 - k);
    poses.push_back({along, 0.02 * 0.5 * k, k <= 40 ? 0.0 : 3.14159});
  }
  return poses;
}

align::LocalAlignment pairs_of(std::vector<std::pair<std::size_t, std::size_t>> pairs) {
  align::LocalAlignment a;
  a.pairs = std::move(pairs);
  return a;
}

TEST(OdometryGate, KeepsTheRevisitAndDropsTheShiftedCopy) {
  const auto odometry = out_and_back();
  // True reverse revisit: image 40 + d is at the same spot as 40 - d.
  std::vector<std::pair<std::size_t, std::size_t>> revisit, shifted;
  for (std::size_t d = 5; d < 30; ++d) revisit.emplace_back(40 + d, 40 - d);
  // The same corridor 10 m further on (a self-similar corridor): image i paired with i - 20 on the way out.
  for (std::size_t i = 20; i < 40; ++i) shifted.emplace_back(i, i - 20);
  const auto keep = consistent_with_odometry({pairs_of(revisit), pairs_of(shifted)}, odometry);
  EXPECT_TRUE(keep[0]);
  EXPECT_FALSE(keep[1]);
  EXPECT_EQ(odometry_verdicts({pairs_of(revisit), pairs_of(shifted)}, odometry),
            (std::vector<OdometryVerdict>{OdometryVerdict::consistent, OdometryVerdict::apart}));
  // A loose enough gate lets the shifted copy through: 10 m apart after 10 m of travel.
  EXPECT_TRUE(consistent_with_odometry({pairs_of(shifted)}, odometry, {.base = 0.1, .drift = 1.0})[0]);
}

TEST(OdometryGate, CountsConsistentPairsAgainstTheFraction) {
  const auto odometry = out_and_back();
  // Half the pairs are true revisits, half are 10 m off.
  std::vector<std::pair<std::size_t, std::size_t>> mixed;
  for (std::size_t d = 10; d < 20; ++d) mixed.emplace_back(40 + d, 40 - d);
  for (std::size_t i = 20; i < 30; ++i) mixed.emplace_back(i, i - 20);
  // Brute force: the consistent fraction, from the rule in the header.
  std::size_t consistent = 0;
  for (auto [i, j] : mixed) {
    double travelled = 0;
    for (std::size_t k = std::min(i, j) + 1; k <= std::max(i, j); ++k) {
      travelled += std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y);
    }
    consistent += std::hypot(odometry[i].x - odometry[j].x, odometry[i].y - odometry[j].y) <= 2.0 + 0.1 * travelled;
  }
  const double fraction = static_cast<double>(consistent) / static_cast<double>(mixed.size());
  EXPECT_DOUBLE_EQ(fraction, 0.5);
  EXPECT_TRUE(consistent_with_odometry({pairs_of(mixed)}, odometry, {.min_consistent = 0.5})[0]);
  EXPECT_FALSE(consistent_with_odometry({pairs_of(mixed)}, odometry, {.min_consistent = 0.6})[0]);
}

// Two traversals of one 20 m stretch (x = 0..20 at 0.5 m an image), each arriving from and leaving towards
// another side: the first from the north and on to the north, the second from the south and on to the south.
// The second traversal's odometry is in a frame of its own (turned by 30 degrees and moved), as after a
// kidnapping. `lateral(x)`: the second traversal's sideways offset along the stretch. Images 0..70 are the
// first traversal, 71..141 the second; image 71 + k is at the k-th position.
std::vector<Pose2> two_traversals_parting(double (*lateral)(double)) {
  std::vector<Pose2> poses;
  const auto position = [](int k, int side, double offset) {
    if (k < 10) return Pose2{0, side * (5.0 - 0.5 * k) + offset, 0};
    if (k <= 50) return Pose2{0.5 * (k - 10), offset, 0};
    return Pose2{20, side * 0.5 * (k - 50) + offset, 0};
  };
  for (int k = 0; k <= 70; ++k) poses.push_back(position(k, 1, 0));
  const double c = std::cos(0.5236), s = std::sin(0.5236);
  for (int k = 0; k <= 70; ++k) {
    const Pose2 p = position(k, -1, 0);
    const double y = p.y + lateral(p.x);
    poses.push_back({c * p.x - s * y + 100, s * p.x + c * y + 50, 0});
  }
  return poses;
}

std::vector<std::pair<std::size_t, std::size_t>> diagonal(std::size_t from, std::size_t to) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t k = from; k <= to; ++k) pairs.emplace_back(71 + k, k);
  return pairs;
}

TEST(OdometryGate, TrimsTheEndsWherePathsPart) {
  const auto poses = two_traversals_parting([](double) { return 0.0; });
  OdometryGate gate;
  gate.base = 2.5;
  gate.trim_floor = 2.5;  // the tolerance: the middle's scatter is 0 here
  // Where the arms part the two images are 2 (10 - k) m apart before the stretch (k < 10) and 2 (k - 50)
  // m after it: within 2.5 m for k = 8..52.
  const auto trimmed = trim_to_odometry({pairs_of(diagonal(0, 70))}, poses, gate).front();
  EXPECT_EQ(trimmed.pairs, diagonal(8, 52));
  EXPECT_EQ(trimmed.a_begin, 71U + 8);
  EXPECT_EQ(trimmed.a_end, 71U + 53);
  EXPECT_EQ(trimmed.b_begin, 8U);
  EXPECT_EQ(trimmed.b_end, 53U);
  // Within the stretch nothing is trimmed; without a window nothing at all.
  EXPECT_EQ(trim_to_odometry({pairs_of(diagonal(12, 48))}, poses, gate).front().pairs, diagonal(12, 48));
  gate.trim_window = 0;
  EXPECT_EQ(trim_to_odometry({pairs_of(diagonal(0, 70))}, poses, gate).front().pairs, diagonal(0, 70));
}

TEST(OdometryGate, TheToleranceFollowsTheMiddlesScatter) {
  // Noise-free shapes are trimmed at the floor: the arms are within 1 m for k = 10 (0 m)... only 9..51 can
  // stay (1 m apart at the boundary, so the test asks for the safe side: at least 10..50, at most 8..52).
  OdometryGate gate;
  gate.base = 3;
  gate.trim_floor = 1.2;
  const auto exact =
      trim_to_odometry({pairs_of(diagonal(0, 70))}, two_traversals_parting([](double) { return 0.0; }), gate).front();
  EXPECT_EQ(exact.pairs, diagonal(9, 51));
  // A pass zig-zagging 1 m about the path scatters about 0.7 m in the middle: the tolerance grows to about
  // 2 m, so the same parting keeps more pairs, and still drops the arms' far ends.
  const auto zigzag = two_traversals_parting([](double x) { return std::sin(2 * 3.14159265 * x / 3); });
  const auto wide = trim_to_odometry({pairs_of(diagonal(0, 70))}, zigzag, gate).front();
  EXPECT_GT(wide.pairs.size(), exact.pairs.size());
  EXPECT_LT(wide.pairs.size(), diagonal(0, 70).size() - 20);
  // Never beyond base.
  gate.base = 1.2;
  EXPECT_LE(trim_to_odometry({pairs_of(diagonal(0, 70))}, zigzag, gate).front().pairs.size(), wide.pairs.size());
}

TEST(OdometryGate, KeepsParallelZigZagAndReversePasses) {
  const OdometryGate gate;  // base 2 m
  // A parallel lane 1.5 m to the side, and a pass zig-zagging 0.6 m about the path: the shapes agree.
  const auto lane = two_traversals_parting([](double) { return 1.5; });
  EXPECT_EQ(trim_to_odometry({pairs_of(diagonal(10, 50))}, lane, gate).front().pairs, diagonal(10, 50));
  const auto zigzag = two_traversals_parting([](double x) { return 0.6 * std::sin(2 * 3.14159265 * x / 3); });
  EXPECT_EQ(trim_to_odometry({pairs_of(diagonal(10, 50))}, zigzag, gate).front().pairs, diagonal(10, 50));
  // The same stretch driven back: the second traversal's k-th image pairs with the first's (60 - k).
  std::vector<std::pair<std::size_t, std::size_t>> reverse;
  for (std::size_t k = 10; k <= 50; ++k) reverse.emplace_back(71 + k, 60 - k);
  EXPECT_EQ(trim_to_odometry({pairs_of(reverse)}, lane, gate).front().pairs, reverse);
  // A robot that did not move: nothing to compare, nothing trimmed.
  const std::vector<Pose2> still(142, Pose2{1, 2, 0});
  EXPECT_EQ(trim_to_odometry({pairs_of(diagonal(0, 70))}, still, gate).front().pairs, diagonal(0, 70));
}

// Two passes of a 20 m stretch (41 images at 0.5 m): the first east along y = 0 (images 0..40), the second
// (images 41..81) the same positions turned by `turn` about the stretch's middle (10, 0), as odometry whose
// heading drifted by that much between them.
std::vector<Pose2> second_pass_turned(double turn) {
  std::vector<Pose2> poses;
  for (int k = 0; k <= 40; ++k) poses.push_back({0.5 * k, 0, 0});
  for (int k = 0; k <= 40; ++k) {
    const double x = 0.5 * k - 10;
    poses.push_back({10 + std::cos(turn) * x, std::sin(turn) * x, turn});
  }
  return poses;
}

TEST(OdometryGate, DropsALookAlikeWhoseTraversalsMoveAgainstTheAlignment) {
  // Two identical corridors side by side, 6 m apart: the first walked east, the second west. The second's image
  // at x looks like the first's at 20 - x (the corridor turned round), so a forward alignment pairs images that
  // cross at mid-corridor. A distance gate loose enough for 6 m passes it; the traversals' rotation does not.
  std::vector<Pose2> odometry;
  for (int k = 0; k <= 40; ++k) odometry.push_back({0.5 * k, 0, 0});
  for (int k = 0; k <= 40; ++k) odometry.push_back({20 - 0.5 * k, 6, 3.14159});
  std::vector<std::pair<std::size_t, std::size_t>> look_alike, beside;
  for (std::size_t k = 0; k <= 40; ++k) look_alike.emplace_back(41 + k, k);
  // Paired with the image beside it (a reverse alignment of parallel lanes): the traversals turn by nothing.
  for (std::size_t k = 0; k <= 40; ++k) beside.emplace_back(41 + k, 40 - k);
  const OdometryGate loose{.base = 25};
  EXPECT_EQ(consistent_with_odometry({pairs_of(look_alike), pairs_of(beside)}, odometry, loose),
            (std::vector<bool>{false, true}));
  EXPECT_EQ(odometry_verdicts({pairs_of(look_alike), pairs_of(beside)}, odometry, loose),
            (std::vector<OdometryVerdict>{OdometryVerdict::turned, OdometryVerdict::consistent}));
  // At the default allowance (2 m + 10 % of the 26 m between the passes) the 6 m apart come first.
  EXPECT_EQ(odometry_verdicts({pairs_of(look_alike)}, odometry).front(), OdometryVerdict::apart);
  // Without the rotation allowance's limit (turn large) both pass; the distance rule alone cannot tell.
  EXPECT_EQ(consistent_with_odometry({pairs_of(look_alike), pairs_of(beside)}, odometry, {.base = 25, .turn = 1}),
            (std::vector<bool>{true, true}));
  // Three pairs 1 m long (rms 0.41 m about their centre): too short a stretch to read a direction from.
  EXPECT_TRUE(consistent_with_odometry({pairs_of({{60, 20}, {61, 21}, {62, 22}})}, odometry, loose)[0]);
}

TEST(OdometryGate, TurnAllowanceIsARightAnglePlusTheHeadingDriftOverTheTravel) {
  const std::vector<std::pair<std::size_t, std::size_t>> revisit = [] {
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t k = 0; k <= 40; ++k) pairs.emplace_back(41 + k, k);
    return pairs;
  }();
  const OdometryGate gate{.base = 100, .turn = 0.01};
  for (const double turn : {0.3, 1.0, 1.5, 1.8, 2.0, 2.2, 2.6, 3.0}) {
    const auto odometry = second_pass_turned(turn);
    // Brute force from the header's rule: the median over the pairs of the path length between them.
    std::vector<double> between;
    for (auto [i, j] : revisit) {
      double travelled = 0;
      for (std::size_t k = j + 1; k <= i; ++k) {
        travelled += std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y);
      }
      between.push_back(travelled);
    }
    std::nth_element(between.begin(), between.begin() + 20, between.end());
    const bool expected = turn <= 3.14159265358979 / 2 + 0.01 * between[20];
    EXPECT_EQ(consistent_with_odometry({pairs_of(revisit)}, odometry, gate)[0], expected) << turn;
  }
  // The allowance around this geometry (travel about 20-40 m) lies between 1.8 and 2.2 rad: both sides are tested.
  EXPECT_TRUE(consistent_with_odometry({pairs_of(revisit)}, second_pass_turned(1.8), gate)[0]);
  EXPECT_FALSE(consistent_with_odometry({pairs_of(revisit)}, second_pass_turned(2.2), gate)[0]);
}

TEST(OdometryGate, RejectsBadInput) {
  const auto odometry = out_and_back();
  EXPECT_THROW(consistent_with_odometry({pairs_of({{90, 1}})}, odometry), std::invalid_argument);
  EXPECT_THROW(consistent_with_odometry({}, odometry, {.base = -1}), std::invalid_argument);
  EXPECT_THROW(consistent_with_odometry({}, odometry, {.min_consistent = 1.5}), std::invalid_argument);
  EXPECT_THROW(consistent_with_odometry({}, odometry, {.turn = -0.1}), std::invalid_argument);
  EXPECT_FALSE(consistent_with_odometry({pairs_of({})}, odometry)[0]);
  EXPECT_THROW(trim_to_odometry({pairs_of({{90, 1}, {91, 2}, {92, 3}})}, odometry), std::invalid_argument);
  EXPECT_THROW(trim_to_odometry({pairs_of({})}, odometry, {.trim_window = -1}), std::invalid_argument);
}

TEST(OdometryGate, BuildMapDropsContradictedAlignmentsBeforePruning) {
  // Similarity with two bright stripes: the true reverse revisit and a forward copy 20 images apart.
  const auto odometry = out_and_back();
  const std::size_t n = odometry.size();
  SimilarityMatrix s(n, n, 0.0F);
  for (std::size_t d = 5; d < 30; ++d) s(40 + d, 40 - d) = s(40 - d, 40 + d) = 1.0F;
  for (std::size_t i = 20; i < 40; ++i) s(i, i - 20) = s(i - 20, i) = 1.0F;
  MapConfig config;
  config.score.contrast_window = 0;
  config.search.cap.reset();
  config.significance.threshold = 5;
  for (auto& v : s.values) v -= 0.3F;
  const MapResult without = build_map(s, config);
  const MapResult with = build_map(s, config, odometry);
  EXPECT_EQ(without.alignments.size(), with.alignments.size() + with.rejected.size());
  ASSERT_EQ(with.rejected.size(), 1U);
  EXPECT_EQ(with.rejected.front().direction, align::Direction::forward);
  EXPECT_EQ(with.rejected_verdicts, std::vector<OdometryVerdict>{OdometryVerdict::apart});
  for (const auto& a : with.alignments) EXPECT_EQ(a.direction, align::Direction::reverse);
  // Without the gate the copy merges images 20 apart; with it, no image shares a place with one 20 away.
  EXPECT_EQ(without.map.labels[30], without.map.labels[10]);
  EXPECT_NE(with.map.labels[30], with.map.labels[10]);
  config.odometry.gate.reset();
  EXPECT_TRUE(build_map(s, config, odometry).rejected.empty());
  EXPECT_THROW(build_map(s, config, std::span(odometry).first(10)), std::invalid_argument);
}

TEST(OdometryGate, AgreementIsTheMedianOfThePairsDistanceOverTheAllowance) {
  const auto odometry = out_and_back();
  std::vector<std::pair<std::size_t, std::size_t>> revisit, shifted;
  for (std::size_t d = 5; d < 30; ++d) revisit.emplace_back(40 + d, 40 - d);
  for (std::size_t i = 20; i < 40; ++i) shifted.emplace_back(i, i - 20);
  // Brute force, from the header's rule: the median of distance / (base + drift x travelled).
  const auto brute = [&](const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
    std::vector<double> r;
    for (auto [i, j] : pairs) {
      double travelled = 0;
      for (std::size_t k = std::min(i, j) + 1; k <= std::max(i, j); ++k) {
        travelled += std::hypot(odometry[k].x - odometry[k - 1].x, odometry[k].y - odometry[k - 1].y);
      }
      r.push_back(std::hypot(odometry[i].x - odometry[j].x, odometry[i].y - odometry[j].y) / (2.0 + 0.1 * travelled));
    }
    std::sort(r.begin(), r.end());
    return r[r.size() / 2];
  };
  const auto agreement = odometry_agreement({pairs_of(revisit), pairs_of(shifted), pairs_of({})}, odometry);
  ASSERT_EQ(agreement.size(), 3U);
  EXPECT_NEAR(agreement[0], brute(revisit), 1e-12);
  EXPECT_NEAR(agreement[1], brute(shifted), 1e-12);
  EXPECT_LT(agreement[0], 0.5);  // the sideways drift only
  EXPECT_GT(agreement[1], 1.0);  // 10 m off after 10 m: outside the gate
  EXPECT_TRUE(std::isinf(agreement[2]));
}

// A reverse revisit planted in noise, walked out and back with odometry: agreement with the odometry lowers its
// E-value by q / exp(-r^2 / 2) (MapConfig::odometry_evidence), so there is a strength at which only the evidence
// makes it significant, and none at which the evidence takes significance away.
TEST(OdometryGate, AgreementIsEvidenceForAWeakRevisit) {
  const std::size_t n = 400, half = n / 2;
  std::vector<Pose2> odometry;
  for (std::size_t k = 0; k < n; ++k) {
    const double along = 0.5 * static_cast<double>(k < half ? k : n - 1 - k);
    odometry.push_back({along, 0.01 * static_cast<double>(k), k < half ? 0.0 : 3.14159});
  }
  bool only_with_evidence = false;
  for (float strength : {0.78F, 0.79F, 0.8F, 0.81F, 0.82F, 0.83F, 0.84F, 0.86F}) {
    std::mt19937 rng(11);
    std::normal_distribution<float> z(0.0F, 1.0F);
    SimilarityMatrix s(n, n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j <= i; ++j) s(i, j) = s(j, i) = i == j ? 3.0F : z(rng);
    }
    for (std::size_t d = 40; d < 100; ++d) {
      s(half + d, half - 1 - d) = s(half - 1 - d, half + d) = s(half + d, half - 1 - d) + strength;
    }
    const auto on_revisit = [&](const MapResult& r) {
      for (std::size_t k = 0; k < r.alignments.size(); ++k) {
        const auto& a = r.alignments[k];
        if (a.direction == align::Direction::reverse && a.a_begin >= half + 30 && a.a_end <= half + 110) return k;
      }
      return r.alignments.size();
    };
    MapConfig config;
    const MapResult with = build_map(s, config, odometry);
    config.odometry.evidence = false;
    const MapResult without = build_map(s, config, odometry);
    const double q = with.decisions.odometry_chance_agreement;
    ASSERT_GT(q, 0.0) << strength;
    ASSERT_LT(q, 1.0) << strength;
    EXPECT_EQ(without.decisions.odometry_chance_agreement, 1.0);
    const std::size_t a = on_revisit(with), b = on_revisit(without);
    const bool found_with = a < with.alignments.size(), found_without = b < without.alignments.size();
    EXPECT_TRUE(found_with || !found_without) << "the evidence took a revisit away at strength " << strength;
    if (found_with && found_without && with.alignments[a].pairs == without.alignments[b].pairs) {
      const double r = odometry_agreement({with.alignments[a]}, odometry).front();
      EXPECT_NEAR(with.e_values[a], without.e_values[b] * std::min(1.0, q / std::exp(-0.5 * r * r)),
                  1e-9 * without.e_values[b])
          << strength;
    }
    only_with_evidence = only_with_evidence || (found_with && !found_without);
  }
  EXPECT_TRUE(only_with_evidence) << "no strength at which only the odometry's evidence makes the revisit";
}

}  // namespace
}  // namespace seqtopo::mapping
