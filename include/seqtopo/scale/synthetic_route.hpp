#pragma once
// Synthetic descriptors of a robot's route with known revisits, for measuring the scale modes
// (`seqtopo bench scale`, seqtopo-mpi's test) without a data set.
//
// The places are a random walk on the unit sphere (consecutive places: cosine ~0.97), each frame an
// observation of its place with noise (cosine ~0.9). The first half explores; the second half
// alternates 250-frame revisits of the first half (forward, then backward) with 250 frames of new
// exploration. The same n, dim and seed give the same descriptors.
#include <cstddef>
#include <vector>

namespace seqtopo::scale {

struct SyntheticRoute {
  std::vector<float> descriptors;  // n x dim, row-major (not normalised)
  std::vector<long> truth;         // the first-half frame that frame i revisits, or -1
};

SyntheticRoute synthetic_route(std::size_t n, std::size_t dim, unsigned seed);

}  // namespace seqtopo::scale
