#include "seqtopo/similarity/distance.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "kernels.hpp"

namespace seqtopo::similarity {
namespace {

void check_lengths(std::span<const float> a, std::span<const float> b) {
  if (a.size() != b.size()) {
    throw std::invalid_argument("descriptors differ in length: " + std::to_string(a.size()) + " and " +
                                std::to_string(b.size()));
  }
}

void check_dimensions(const SparseHistogram& a, const SparseHistogram& b) {
  if (a.dimension != b.dimension) {
    throw std::invalid_argument("histograms differ in dimension: " + std::to_string(a.dimension) + " and " +
                                std::to_string(b.dimension));
  }
}

}  // namespace

std::string_view distance_name(Distance metric) {
  switch (metric) {
    case Distance::chi2:
      return "chi2";
    case Distance::l1:
      return "l1";
    case Distance::cosine:
      return "cosine";
    case Distance::sad:
      return "sad";
  }
  return "?";
}

Distance parse_distance(std::string_view name) {
  if (name == "chi2") return Distance::chi2;
  if (name == "l1") return Distance::l1;
  if (name == "cosine") return Distance::cosine;
  if (name == "sad") return Distance::sad;
  throw std::invalid_argument("unknown metric '" + std::string(name) + "' (expected chi2, l1, cosine or sad)");
}

double chi2_distance(std::span<const float> a, std::span<const float> b) {
  check_lengths(a, b);
  return detail::dense_chi2(a.data(), b.data(), a.size());
}

double l1_distance(std::span<const float> a, std::span<const float> b) {
  check_lengths(a, b);
  return detail::dense_l1(a.data(), b.data(), a.size());
}

double cosine_distance(std::span<const float> a, std::span<const float> b) {
  check_lengths(a, b);
  return detail::cosine_from_dot(detail::dense_dot(a.data(), b.data(), a.size()),
                                 detail::lane_sum_squares(a.data(), a.size()),
                                 detail::lane_sum_squares(b.data(), b.size()));
}

double squared_norm(std::span<const float> a) { return detail::lane_sum_squares(a.data(), a.size()); }

double cosine_distance(std::span<const float> a, std::span<const float> b, double norm2_a, double norm2_b) {
  check_lengths(a, b);
  return detail::cosine_from_dot(detail::dense_dot(a.data(), b.data(), a.size()), norm2_a, norm2_b);
}

double sad_distance(std::span<const float> a, std::span<const float> b) {
  check_lengths(a, b);
  return a.empty() ? 0.0 : detail::dense_l1(a.data(), b.data(), a.size()) / static_cast<double>(a.size());
}

double distance(Distance metric, std::span<const float> a, std::span<const float> b) {
  switch (metric) {
    case Distance::chi2:
      return chi2_distance(a, b);
    case Distance::l1:
      return l1_distance(a, b);
    case Distance::cosine:
      return cosine_distance(a, b);
    case Distance::sad:
      return sad_distance(a, b);
  }
  throw std::invalid_argument("unknown metric");
}

double chi2_distance(const SparseHistogram& a, const SparseHistogram& b) { return distance(Distance::chi2, a, b); }

double distance(Distance metric, const SparseHistogram& a, const SparseHistogram& b) {
  check_dimensions(a, b);
  // The matrix's kernel with A alone in row 0, so that both give the same value to the last bit.
  std::vector<float> a8(static_cast<std::size_t>(a.dimension) * detail::kRows, 0.0F);
  for (std::size_t k = 0; k < a.bins.size(); ++k) a8[static_cast<std::size_t>(a.bins[k]) * detail::kRows] = a.values[k];
  double sums[detail::kRows];
  const std::size_t n = b.bins.size();
  switch (metric) {
    case Distance::chi2:
    case Distance::l1:
    case Distance::sad: {
      detail::sparse_sums(metric == Distance::chi2 ? detail::SparseSum::chi2 : detail::SparseSum::l1, a8.data(),
                          b.bins.data(), b.values.data(), n, sums);
      const double d = detail::sparse_sum(a.values.data(), a.values.size()) + sums[0];
      return metric == Distance::sad ? (a.dimension == 0 ? 0.0 : d / a.dimension) : d;
    }
    case Distance::cosine:
      detail::sparse_sums(detail::SparseSum::dot, a8.data(), b.bins.data(), b.values.data(), n, sums);
      return detail::cosine_from_dot(sums[0], detail::sparse_sum_squares(a.values.data(), a.values.size()),
                                     detail::sparse_sum_squares(b.values.data(), b.values.size()));
  }
  throw std::invalid_argument("unknown metric");
}

}  // namespace seqtopo::similarity
