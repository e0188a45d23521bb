#pragma once
// Does a confidence read as a probability? The reliability diagram and the expected calibration error
// (Naeini, Cooper & Hauskrecht 2015; Guo et al. 2017): detections binned by confidence into equal-width bins;
// in each, the mean confidence against the share that is right; ECE = sum over bins of (share of detections)
// x |accuracy - mean confidence|. 0 is perfectly calibrated.
#include <cstddef>
#include <vector>

namespace seqtopo::evaluation {

struct ReliabilityBin {
  double lower = 0, upper = 0;  // confidence range [lower, upper) (the last bin includes 1)
  std::size_t count = 0;
  double mean_confidence = 0, accuracy = 0;  // 0 when empty
};

struct Calibration {
  double ece = 0;
  std::size_t detections = 0;
  std::vector<ReliabilityBin> bins;
};

// confidence[k] in [0, 1] (clamped) and correct[k] describe detection k. Throws std::invalid_argument when the
// sizes differ or bins is 0.
Calibration calibration(const std::vector<double>& confidence, const std::vector<bool>& correct, std::size_t bins = 10);

}  // namespace seqtopo::evaluation
