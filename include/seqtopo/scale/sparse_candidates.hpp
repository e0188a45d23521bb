#pragma once
// Candidate pairs for the sparse mode: the approximate nearest neighbours of every frame (FAISS), and
// the sparse score matrix that keeps the exact mapping score at those pairs and a constant elsewhere.
//
// Index: the normalised descriptors (cosine = inner product) in a FAISS IndexIVFFlat (inverted lists
// over k-means cells, exact inner products inside the probed lists), or brute force (IndexFlatIP) with
// `exact`. Determinism: k-means is seeded (`seed`) and trained on a seeded subsample, and the search is
// exact within the probed lists, so the candidates do not depend on the thread count; they can differ
// between BLAS builds in the last bits of a tie. (HNSW was not chosen: its parallel insertion makes
// the graph depend on thread scheduling.)
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"

namespace seqtopo::scale {

struct CandidateConfig {
  std::size_t neighbours = 10;  // k: candidates per frame, after the exclusion below
  std::size_t exclude = 10;     // [frames] neighbours closer in time than this are skipped (min_separation)
  bool exact = false;           // brute force instead of the inverted-file index
  std::size_t lists = 0;        // inverted lists; 0 = 2 sqrt(N), at most N / 39
  std::size_t probes = 8;       // lists searched per query
  int seed = 1234;              // k-means seed
  // Each neighbour pair (i, j) also brings (i +- t, j +- t) and (i +- t, j -+ t) for t = 1 .. reach:
  // the diagonal and anti-diagonal around it, where a revisit's other pairs lie when single frames
  // are too ambiguous for their true match to be among the k nearest (strong appearance change).
  std::size_t diagonal_reach = 0;
};

struct CandidateStats {
  std::size_t pairs = 0;     // distinct cells (i, j) with a candidate score (both triangles)
  double seconds_index = 0;  // training and adding
  double seconds_search = 0;
  double seconds_scores = 0;
};

// For each frame, up to `neighbours` frames j with |i - j| >= exclude, largest inner product first.
// descriptors: n x dim, row-major, normalised. Throws std::invalid_argument on a size mismatch.
std::vector<std::vector<std::uint32_t>> nearest_neighbours(std::span<const float> descriptors, std::size_t n,
                                                           std::size_t dim, const CandidateConfig& config = {},
                                                           CandidateStats* stats = nullptr);

// The sparse mode's score matrix: the union of the neighbour pairs, both ways, each with the exact
// mapping score similarity.score(i, j); `background` everywhere else.
SparseScores sparse_map_scores(const StreamingSimilarity& similarity, float background,
                               const CandidateConfig& config = {}, CandidateStats* stats = nullptr);

}  // namespace seqtopo::scale
