#include "seqtopo/simulator/descriptor_sequences.hpp"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace seqtopo::simulator {

DescriptorSequence make_descriptor_sequence(const DescriptorSequenceConfig& c) {
  if (c.frames == 0 || c.dim == 0 || c.repeat == 0) throw std::invalid_argument("frames, dim and repeat must be > 0");
  for (const auto& r : c.revisits) {
    if (r.source + r.length > c.frames || r.target + r.length > c.frames) {
      throw std::invalid_argument("planted revisit " + std::to_string(r.target) + " + " + std::to_string(r.length) +
                                  " does not fit in " + std::to_string(c.frames) + " frames");
    }
    if (r.target < r.source + r.length && r.source < r.target + r.length) {
      throw std::invalid_argument("a planted revisit overlaps its source");
    }
  }
  std::mt19937_64 random(c.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  DenseMatrix<double> x(c.frames, c.dim, 0.0);
  const double rho = c.texture == Texture::ar1 ? std::exp(-1.0 / c.correlation_length) : 0.0;
  const double innovation = std::sqrt(1.0 - rho * rho);
  for (std::size_t i = 0; i < c.frames; ++i) {
    for (std::size_t d = 0; d < c.dim; ++d) {
      const double e = normal(random);
      switch (c.texture) {
        case Texture::white:
          x(i, d) = e;
          break;
        case Texture::walk:
          x(i, d) = (i ? x(i - 1, d) : 0.0) + e;
          break;
        case Texture::ar1:
          x(i, d) = i ? rho * x(i - 1, d) + innovation * e : e;
          break;
      }
    }
  }
  std::vector<double> position(c.frames);
  for (std::size_t i = 0; i < c.frames; ++i) position[i] = static_cast<double>(i);
  for (const auto& r : c.revisits) {
    for (std::size_t k = 0; k < r.length; ++k) {
      const std::size_t from = r.reverse ? r.source + r.length - 1 - k : r.source + k;
      for (std::size_t d = 0; d < c.dim; ++d) x(r.target + k, d) = x(from, d) + r.noise * normal(random);
      position[r.target + k] = position[from];
    }
  }
  DescriptorSequence out;
  out.descriptors = DenseMatrix<float>(c.frames * c.repeat, c.dim);
  for (std::size_t i = 0; i < c.frames; ++i) {
    for (std::size_t k = 0; k < c.repeat; ++k) {
      for (std::size_t d = 0; d < c.dim; ++d) out.descriptors(i * c.repeat + k, d) = static_cast<float>(x(i, d));
      out.position.push_back(position[i]);
    }
  }
  return out;
}

}  // namespace seqtopo::simulator
