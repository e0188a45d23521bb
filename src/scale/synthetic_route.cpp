#include "seqtopo/scale/synthetic_route.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace seqtopo::scale {

SyntheticRoute synthetic_route(std::size_t n, std::size_t dim, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> g(0.0F, 1.0F);
  const float step = 0.25F / std::sqrt(static_cast<float>(dim));  // consecutive places: cosine ~0.97
  const float look = 0.45F / std::sqrt(static_cast<float>(dim));  // observation noise: cosine ~0.9
  std::vector<float> place(dim), walk(dim);
  auto normalise = [](std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += static_cast<double>(x) * x;
    const auto inv = static_cast<float>(1.0 / std::sqrt(s));
    for (float& x : v) x *= inv;
  };
  for (float& x : walk) x = g(rng);
  normalise(walk);
  const std::size_t half = n / 2;
  std::vector<float> places(half * dim);
  SyntheticRoute r;
  r.descriptors.resize(n * dim);
  r.truth.assign(n, -1);
  auto advance = [&] {
    for (float& x : walk) x += step * g(rng);
    normalise(walk);
  };
  auto observe = [&](std::size_t i, const float* p) {
    for (std::size_t t = 0; t < dim; ++t) r.descriptors[i * dim + t] = p[t] + look * g(rng);
  };
  for (std::size_t i = 0; i < half; ++i) {
    advance();
    std::copy(walk.begin(), walk.end(), places.begin() + static_cast<std::ptrdiff_t>(i * dim));
    observe(i, walk.data());
  }
  const std::size_t block = 250;
  for (std::size_t b0 = half, k = 0; b0 < n; b0 += block, ++k) {
    const std::size_t len = std::min(block, n - b0);
    if (k % 2 == 0 && half > block) {
      const std::size_t start = std::uniform_int_distribution<std::size_t>(0, half - block)(rng);
      const bool backward = (k / 2) % 2 == 1;
      for (std::size_t a = 0; a < len; ++a) {
        const std::size_t p = backward ? start + block - 1 - a : start + a;
        observe(b0 + a, places.data() + p * dim);
        r.truth[b0 + a] = static_cast<long>(p);
      }
    } else {
      for (std::size_t a = 0; a < len; ++a) {
        advance();
        observe(b0 + a, walk.data());
      }
    }
  }
  return r;
}

}  // namespace seqtopo::scale
