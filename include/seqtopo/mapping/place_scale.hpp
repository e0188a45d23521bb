#pragma once
// How many consecutive frames show one place: the scale in which a sequence's windows and separations are
// counted, so that the same route recorded at another frame rate gives the same map (docs/significance.md).
//
// Estimate from the images: the similarity of frame i to frame i + k falls as k grows; c(k) is its median over
// i and c_far the median of c over the far lags [K/2, K] (K = min(max_lag, N / 3)). The scale is the
// similarity's half-life: the lag at which (c(k) - c_far) / (c(0) - c_far) first falls below 1/2,
// interpolated linearly between lags, and at least 1.
// A frame repeated r times has r identical neighbours before the decay starts, so the estimate grows r-fold;
// frames farther apart than a place (a low frame rate) give 1. A sequence without a scale - the similarity
// still falling at the far lags, (c(K/2) - c(K)) / (c(0) - c(K)) > 0.2, as for a random walk, whose frames
// drift apart at every scale - gives 1 with `found` false; so does an estimate above N / 50 (a sequence of
// fewer than 50 places is taken to drift), which is clamped there.
//
// Above kPlaceScaleFrames frames the medians are over every s-th frame, s = ceil(N / kPlaceScaleFrames): the
// estimate holds (lags + 1) x min(N, kPlaceScaleFrames) scores, not (lags + 1) x N (800 MB at 10^6 frames).
//
// Worked example: AR(1) descriptors x_{i+1} = rho x_i + sqrt(1 - rho^2) e_i with rho = exp(-1 / L) have
// cosine similarity close to exp(-k / L) at lag k: the estimate is L ln 2.
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "seqtopo/align/score_source.hpp"
#include "seqtopo/core/pose2.hpp"

namespace seqtopo::mapping {

struct PlaceScale {
  double frames_per_place = 1;  // 1 when not found
  bool found = false;           // false: too short a sequence, or no decay to a flat background
};

inline constexpr std::size_t kPlaceScaleFrames = 100000;

// `similarity` is a square self-similarity (higher = more similar; any scale). Throws std::invalid_argument on
// a non-square or empty source.
PlaceScale estimate_frames_per_place(const align::ScoreSource& similarity, std::size_t max_lag = 200);

// The same estimate from samples already read: by_lag[k] holds S(i, i + k) for the sampled frames i of a sequence
// of n frames (by_lag.size() - 1 lags, emptied). For a sequence seen a frame at a time (mapping::OnlineMapper).
PlaceScale frames_per_place_from_lags(std::vector<std::vector<float>> by_lag, std::size_t n);

// With odometry the scale is the travelled distance instead: place_length [m] over the median distance between
// consecutive poses, at least 1 (found is false when the robot does not move). The default place length is the
// mapping paper's indoor recording interval (one image every 0.25 m, section V), so a sequence recorded as the
// paper did counts one frame per place, and a 30 fps recording at 1 m/s about 7.5.
PlaceScale frames_per_place_from_odometry(std::span<const Pose2> odometry, double place_length = 0.25);

// The scale a map run uses: the travelled distance when there is odometry (a smooth descriptor can look alike
// over many places), else `from_similarity()` (called only then).
PlaceScale place_scale(std::span<const Pose2> odometry, const std::function<PlaceScale()>& from_similarity);

}  // namespace seqtopo::mapping
