#pragma once
// Local contrast enhancement of a similarity matrix (as in SeqSLAM, Milford & Wyeth 2012).
//
// Why: a raw similarity matrix has strong row and column structure - some frames (dark, blurred,
// featureless) are similar to everything, others to nothing - so one global threshold S > 0
// rewards aliasing in some rows and misses true revisits in others. Normalising every cell by the
// mean and standard deviation of its row within +-window columns turns it into "how many standard
// deviations better than its neighbours", which is comparable across the whole matrix.
#include <cstddef>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::similarity {

// Each cell minus the mean of its row within +-window columns, divided by their standard deviation.
// window = 0 returns the matrix unchanged.
SimilarityMatrix enhance_contrast(const SimilarityMatrix& similarity, std::size_t window);

// For a square (self-similarity) matrix: 0.5 (E + E^T) - offset, with E = enhance_contrast(S, window).
// Symmetric again, and positive only where a cell stands out by more than `offset` standard
// deviations: the alignment rewards those and penalises the rest.
SimilarityMatrix enhance_contrast_symmetric(const SimilarityMatrix& similarity, std::size_t window, float offset);

}  // namespace seqtopo::similarity
