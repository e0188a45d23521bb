#pragma once
// The settings every engine refuses in the same words (gaps, cap, threshold, self alignment's shape).
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::align::detail {

// Throws std::invalid_argument naming the first unusable setting for a rows x cols search.
inline void check_config(std::size_t rows, std::size_t cols, const AlignConfig& config) {
  auto bad = [](Score v) { return std::isnan(v) || v < 0; };
  if (bad(config.gap_a) || bad(config.gap_b)) throw std::invalid_argument("gap penalties must be >= 0");
  if (config.cap && (std::isnan(*config.cap) || *config.cap <= 0)) throw std::invalid_argument("cap must be > 0");
  if (std::isnan(config.threshold)) throw std::invalid_argument("threshold must be a number");
  if (config.self && rows != cols) {
    throw std::invalid_argument("self alignment needs a square score matrix, got " + std::to_string(rows) + " x " +
                                std::to_string(cols));
  }
  if (config.self && config.min_separation == 0) throw std::invalid_argument("min_separation must be >= 1");
}

}  // namespace seqtopo::align::detail
