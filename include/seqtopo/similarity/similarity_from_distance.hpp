#pragma once
// From distances to the similarity that the alignment scores (mapping paper, section IV-A):
//   S = 1 - kappa * D.
// The alignment rewards a pair with S > 0 and penalises one with S < 0, so kappa decides which pairs count as
// a possible match: exactly those with D < 1 / kappa. The paper set kappa by hand.
//
// kappa auto: each image is assumed to have about `matches_per_image` true partners (a revisited place is
// seen from a couple of neighbouring frames, on one or two revisits). Among the pairs that can be revisits
// (|i - j| >= min_separation in one sequence; every cell between two sequences), the fraction
//   p = matches_per_image / (pairs per image)
// with the smallest distances should get S > 0, so 1 / kappa is the p-quantile q of those distances:
//   kappa = 1 / q.
// Neighbouring frames are left out because they are trivially similar and would otherwise use up the whole
// quantile. The quantile is taken over at most `max_samples` distances picked with a fixed stride, so the
// rule is deterministic and cheap on large matrices.
#include <cstddef>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::similarity {

struct KappaRule {
  double matches_per_image = 5.0;  // expected true partners of one image: a revisit is recognised within +-2 frames
  std::size_t min_separation = 5;  // frames |i - j| < this are not revisits (symmetric case only)
  double max_fraction = 0.25;      // p never exceeds this (short sequences)
  std::size_t max_samples = 4'000'000;
};

struct KappaChoice {
  float kappa = 1.0F;
  double fraction = 0;         // p
  double quantile = 0;         // q = 1 / kappa
  std::size_t candidates = 0;  // pairs the quantile was taken over (before sampling)
};

// `symmetric`: `distances` is the N x N matrix of one sequence (only its lower triangle is read).
KappaChoice choose_kappa(const DenseMatrix<float>& distances, bool symmetric, const KappaRule& rule = {});

// S = 1 - kappa * D, in place. Throws std::invalid_argument for kappa <= 0 or not finite.
SimilarityMatrix similarity_from_distance(DenseMatrix<float> distances, float kappa);

}  // namespace seqtopo::similarity
