#pragma once
// Loop closures checked against odometry before they shape the map.
//
// Why: images alone cannot tell two identical corridors apart, nor a long featureless corridor from
// itself a few metres further on; a sequence alignment that matches them is confident and wrong, and one
// wrong merge joins two parts of the map. Odometry drifts, but slowly: two images taken d metres of travel
// apart cannot be at the same place if odometry puts them much farther apart than its drift over d allows.
// An aligned pair (i, j) is consistent when
//     |p_i - p_j| <= base + drift * (distance travelled between j and i)   (odometry positions p)
// and an alignment is kept when at least `min_consistent` of its pairs are.
#include <cstddef>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/core/pose2.hpp"

namespace seqtopo::mapping {

struct OdometryGate {
  double base = 2.0;            // [m] allowed distance between the two images at zero travel
  double drift = 0.1;           // [m per m travelled] growth of the allowance
  double min_consistent = 0.5;  // fraction of an alignment's pairs that must be consistent
};

// One flag per alignment: true = consistent with the odometry. Throws std::invalid_argument when a pair
// indexes past the odometry or a setting is negative / NaN (min_consistent must be in [0, 1]).
std::vector<bool> consistent_with_odometry(const std::vector<align::LocalAlignment>& alignments,
                                           std::span<const Pose2> odometry, const OdometryGate& gate = {});

}  // namespace seqtopo::mapping
