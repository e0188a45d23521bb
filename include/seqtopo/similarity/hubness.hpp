#pragma once
// Hubness correction of a self-similarity matrix: cross-domain similarity local scaling (CSLS, Conneau et al.
// 2018, after the hubness of nearest-neighbour search, Radovanović, Nanopoulos & Ivanović 2010).
//
// Why: some frames resemble a large part of the sequence for reasons that say nothing about place: dark tunnel
// frames match every other dark frame, a featureless wall every other wall. Contrast enhancement compares a cell
// with its row's neighbourhood, so where such frames alternate with ordinary ones (a run of tunnels, the lights
// out in a corridor) a dark pair still stands out of the daylight around it, and an alignment of dark frames
// with dark frames looks like a revisit far beyond chance (E below 1e-9 on a Nordland season with tunnels).
// Each frame's neighbourhood similarity r(i), the mean of its k highest similarities to frames at least
// min_separation away, is how much it resembles the rest of the sequence anyway; a pair counts by how much more
// alike its two frames are than that:
//   S'(i, j) = S(i, j) - (r(i) + r(j)) / 2.
// Along a route r varies slowly, so the z-scores of contrast enhancement barely move there; where it jumps (a
// hub beside ordinary frames) the hub's cells stop standing out. The same statistic as the per-frame test of
// significance/low_information.hpp.
#include <cstddef>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::similarity {

// r(i) of every frame of a square matrix: the mean of the k highest values of row i over the columns j with
// |i - j| >= min_separation (all of them when fewer; 0 when none). Symmetric matrices give symmetric results.
std::vector<float> neighbourhood_similarity(const SimilarityMatrix& similarity, std::size_t k,
                                            std::size_t min_separation);

// S'(i, j) = S(i, j) - (r(i) + r(j)) / 2 in place (computed in double, rounded once). k = 0 leaves it unchanged.
// Throws std::invalid_argument for a matrix that is not square.
void correct_hubness(SimilarityMatrix& similarity, std::size_t k, std::size_t min_separation);

}  // namespace seqtopo::similarity
