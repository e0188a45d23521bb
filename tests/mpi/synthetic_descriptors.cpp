// Writes the synthetic route of `seqtopo bench scale` as descriptors.npy, for running seqtopo-mpi by
// hand or from a script: synthetic_descriptors N OUT.npy [DIM [SEED]] (defaults 64, 7 as the bench).
#include <cstdlib>
#include <iostream>
#include <string>

#include "seqtopo/io/npy.hpp"
#include "seqtopo/scale/synthetic_route.hpp"

int main(int argc, char** argv) {
  if (argc < 3 || argc > 5) {
    std::cerr << "usage: synthetic_descriptors N OUT.npy [DIM [SEED]]\n";
    return 2;
  }
  const std::size_t n = std::stoull(argv[1]);
  const std::size_t dim = argc > 3 ? std::stoull(argv[3]) : 64;
  const auto seed = static_cast<unsigned>(argc > 4 ? std::stoul(argv[4]) : 7);
  auto route = seqtopo::scale::synthetic_route(n, dim, seed);
  seqtopo::io::write_npy(argv[2], seqtopo::DenseMatrix<float>(n, dim, std::move(route.descriptors)));
  return 0;
}
