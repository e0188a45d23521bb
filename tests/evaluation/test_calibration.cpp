// The reliability diagram and ECE against hand-worked cases and a synthetic model whose truth probability is
// known: detections right with exactly the probability they claim are calibrated, overconfident ones are not.
#include <gtest/gtest.h>

#include <random>

#include "seqtopo/evaluation/calibration.hpp"

namespace seqtopo::evaluation {
namespace {

TEST(Calibration, HandWorkedBins) {
  // Two detections at 0.95 (one right), two at 0.15 (both wrong).
  const auto c = calibration({0.95, 0.95, 0.15, 0.15}, {true, false, false, false}, 10);
  ASSERT_EQ(c.bins.size(), 10U);
  EXPECT_EQ(c.bins[9].count, 2U);
  EXPECT_DOUBLE_EQ(c.bins[9].accuracy, 0.5);
  EXPECT_DOUBLE_EQ(c.bins[9].mean_confidence, 0.95);
  EXPECT_EQ(c.bins[1].count, 2U);
  EXPECT_DOUBLE_EQ(c.bins[1].accuracy, 0.0);
  EXPECT_NEAR(c.ece, 0.5 * 0.45 + 0.5 * 0.15, 1e-12);
  EXPECT_EQ(calibration({1.0}, {true}, 4).bins[3].count, 1U) << "confidence 1 is in the last bin";
}

TEST(Calibration, AModelRightWithTheProbabilityItClaimsIsCalibratedAnOverconfidentOneIsNot) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> claimed, overconfident;
  std::vector<bool> right;
  for (int k = 0; k < 20000; ++k) {
    const double p = u(rng);
    claimed.push_back(p);
    overconfident.push_back(std::min(1.0, 0.3 + p));
    right.push_back(u(rng) < p);
  }
  EXPECT_LT(calibration(claimed, right).ece, 0.02);
  EXPECT_GT(calibration(overconfident, right).ece, 0.2);
}

TEST(Calibration, BadInputIsAnError) {
  EXPECT_THROW(calibration({0.5}, {}, 10), std::invalid_argument);
  EXPECT_THROW(calibration({0.5}, {true}, 0), std::invalid_argument);
  EXPECT_EQ(calibration({}, {}, 10).ece, 0.0);
}

}  // namespace
}  // namespace seqtopo::evaluation
