#pragma once
// Synthetic descriptor sequences with known truth, for the statistics' tests and the generalization benchmark
// (`seqtopo bench generalization`): a sequence of D-dimensional descriptors, one per frame, whose texture is
// white noise (every frame unlike every other), a random walk (frames drift: similar at every scale) or an
// AR(1) process with a known correlation length (x_{i+1} = rho x_i + sqrt(1 - rho^2) e_i, rho = exp(-1 / L),
// so neighbouring frames look alike over about L frames); with revisits planted in it: frames
// [target, target + length) repeat frames [source, source + length) (or the same read backwards), plus white
// noise of the given standard deviation. Every frame has a position along the route (its place): a planted
// frame takes its source's, so the truth is exact. `repeat` repeats every frame r times (a higher frame rate).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::simulator {

enum class Texture { white, walk, ar1 };

struct PlantedRevisit {
  std::size_t source = 0, target = 0, length = 0;  // [frames], before `repeat`
  bool reverse = false;
  double noise = 0.5;  // standard deviation of the noise added to the repeated frames (the texture's is 1)
};

struct DescriptorSequenceConfig {
  std::size_t frames = 2000;
  std::size_t dim = 128;
  Texture texture = Texture::white;
  double correlation_length = 5;  // [frames] of Texture::ar1
  std::vector<PlantedRevisit> revisits{};
  std::size_t repeat = 1;
  std::uint64_t seed = 1;
};

struct DescriptorSequence {
  DenseMatrix<float> descriptors;  // (frames * repeat) x dim
  std::vector<double> position;    // per frame: its place along the route [frames of the source sequence]
};

// Throws std::invalid_argument when a revisit does not fit in the sequence or overlaps its source.
DescriptorSequence make_descriptor_sequence(const DescriptorSequenceConfig& config);

}  // namespace seqtopo::simulator
