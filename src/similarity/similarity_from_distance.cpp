#include "seqtopo/similarity/similarity_from_distance.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace seqtopo::similarity {

KappaChoice choose_kappa(const DenseMatrix<float>& d, bool symmetric, const KappaRule& rule) {
  if (symmetric && !d.square()) throw std::invalid_argument("choose_kappa: a symmetric distance matrix must be square");
  if (!(rule.matches_per_image > 0) || !(rule.max_fraction > 0) || rule.max_fraction > 1) {
    throw std::invalid_argument(
        "choose_kappa: matches_per_image and max_fraction must be positive (max_fraction <= 1)");
  }
  KappaChoice choice;
  if (d.empty()) return choice;

  // Candidate pairs: the lower triangle beyond the band of neighbours (falling back to the whole
  // triangle for very short sequences), or every cell of an N x M matrix.
  std::size_t separation = symmetric ? std::max<std::size_t>(1, rule.min_separation) : 0;
  std::size_t per_image = d.cols;
  if (symmetric) {
    if (d.rows <= separation) separation = 1;
    per_image = d.rows - separation;  // row 0 .. N-1 each have about this many partners beyond the band (both sides)
  }
  std::size_t candidates = 0;
  if (symmetric) {
    const std::size_t m = d.rows - separation;  // pairs with i - j >= s: sum over i of (i - s + 1)
    candidates = m * (m + 1) / 2;
  } else {
    candidates = d.rows * d.cols;
  }
  if (candidates == 0) return choice;  // a single image: nothing to compare, kappa 1
  const std::size_t stride = std::max<std::size_t>(1, (candidates + rule.max_samples - 1) / rule.max_samples);

  std::vector<float> samples;
  samples.reserve(candidates / stride + 1);
  std::size_t k = 0;
  auto take = [&](float v) {
    if (k++ % stride == 0) samples.push_back(v);
  };
  if (symmetric) {
    for (std::size_t i = separation; i < d.rows; ++i) {
      for (std::size_t j = 0; j + separation <= i; ++j) take(d(i, j));
    }
  } else {
    for (float v : d.values) take(v);
  }

  const double fraction = std::min(rule.max_fraction, rule.matches_per_image / static_cast<double>(per_image));
  const std::size_t index =
      std::min(samples.size() - 1, static_cast<std::size_t>(fraction * static_cast<double>(samples.size())));
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(index), samples.end());
  double q = samples[index];
  if (!(q > 0)) {
    // Many identical descriptors: fall back to the smallest positive distance so that S > 0 only for them.
    float smallest = 0;
    for (float v : samples) {
      if (v > 0 && (smallest == 0 || v < smallest)) smallest = v;
    }
    q = smallest > 0 ? smallest : 1.0;
  }
  choice.kappa = static_cast<float>(1.0 / q);
  choice.fraction = fraction;
  choice.quantile = q;
  choice.candidates = candidates;
  return choice;
}

SimilarityMatrix similarity_from_distance(DenseMatrix<float> distances, float kappa) {
  if (!(kappa > 0) || !std::isfinite(kappa)) throw std::invalid_argument("kappa must be a positive finite number");
  for (float& v : distances.values) v = 1.0F - kappa * v;
  return distances;
}

}  // namespace seqtopo::similarity
