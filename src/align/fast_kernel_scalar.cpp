// The portable kernel: the reference the vector kernels must match bit for bit.
#include <cmath>

#include "fast_kernels.hpp"

namespace seqtopo::align::detail {

std::int16_t quantize_one(float value, float scale) {
  float v = value * scale;
  v = v > -32767.0F ? v : -32767.0F;  // also maps NaN to -32767, as the vector max does
  v = v < 32767.0F ? v : 32767.0F;
  return static_cast<std::int16_t>(std::nearbyint(v));
}

void quantize_scalar(const float* in, std::size_t count, float scale, std::int16_t* out) {
  for (std::size_t k = 0; k < count; ++k) out[k] = quantize_one(in[k], scale);
}

std::int16_t row_scalar(const RowJob& job) {
  int left = job.left, best = 0;
  for (std::size_t j = job.lo; j <= job.hi; ++j) {
    int t = std::max(saturate(job.prev[j - 1] + job.score[j]), saturate(job.prev[j] - job.gap_a));
    t = std::min(std::max(t, 0), static_cast<int>(job.cap));
    left = std::max(t, saturate(left - job.gap_b));
    job.cur[j] = static_cast<std::int16_t>(left);
    if (job.column_max) job.column_max[j] = std::max(job.column_max[j], job.cur[j]);
    best = std::max(best, left);
  }
  return static_cast<std::int16_t>(best);
}

}  // namespace seqtopo::align::detail
