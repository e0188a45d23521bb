#pragma once
// Distances between two descriptors (mapping paper, section IV-A). Each function has a dense form (two
// equally long vectors) and, where it makes sense, a sparse-histogram form that gives the same value up to
// rounding. All return a distance >= 0 that is 0 for identical inputs.
#include <span>
#include <string_view>

#include "seqtopo/similarity/sparse_histogram.hpp"

namespace seqtopo::similarity {

enum class Distance {
  chi2,    // paper eq. (1): sum_k (a_k - b_k)^2 / (a_k + b_k), bins with a_k + b_k = 0 skipped. Needs a, b >= 0.
  l1,      // sum_k |a_k - b_k|
  cosine,  // 1 - a.b / (|a| |b|); 0 when both are zero vectors, 1 when only one is
  sad,     // SeqSLAM's sum of absolute differences, divided by the length so it is a per-element mean
};

std::string_view distance_name(Distance metric);
// "chi2", "l1", "cosine", "sad"; throws std::invalid_argument otherwise.
Distance parse_distance(std::string_view name);

double chi2_distance(std::span<const float> a, std::span<const float> b);
double l1_distance(std::span<const float> a, std::span<const float> b);
double cosine_distance(std::span<const float> a, std::span<const float> b);
double sad_distance(std::span<const float> a, std::span<const float> b);
// A vector's squared norm, summed as cosine_distance sums it, and the cosine distance of two vectors whose squared
// norms are known: cosine_distance's value exactly, without their sums again (a frame against every earlier frame of
// its sequence: mapping/online_mapper.hpp).
double squared_norm(std::span<const float> a);
double cosine_distance(std::span<const float> a, std::span<const float> b, double norm2_a, double norm2_b);
// One entry point for the dense form; throws std::invalid_argument when the lengths differ.
double distance(Distance metric, std::span<const float> a, std::span<const float> b);

// Sparse forms: only the stored bins are visited (the dimensions must agree).
double chi2_distance(const SparseHistogram& a, const SparseHistogram& b);
double distance(Distance metric, const SparseHistogram& a, const SparseHistogram& b);

}  // namespace seqtopo::similarity
