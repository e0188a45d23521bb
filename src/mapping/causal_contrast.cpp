#include "seqtopo/mapping/causal_contrast.hpp"

#include <algorithm>
#include <stdexcept>

#include "seqtopo/similarity/contrast_enhancement.hpp"

namespace seqtopo::mapping {

void CausalContrast::add(const std::vector<std::span<const float>>& rows, std::size_t n, std::vector<float>& out) {
  const std::size_t t = rows_;
  const std::size_t w = window_;
  if (n > t) throw std::invalid_argument("causal contrast: more columns asked for than the row has");
  for (const auto& row : rows) {
    if (row.size() != t) throw std::invalid_argument("causal contrast: a row of the wrong length");
  }
  ++rows_;
  out.assign(n, 0.0F);
  if (w == 0) {
    for (const auto& row : rows) {
      for (std::size_t j = 0; j < n; ++j) out[j] += row[j] / static_cast<float>(rows.size());
    }
    return;
  }
  if (recent_.size() != rows.size()) recent_.assign(rows.size(), std::vector<std::vector<float>>(w + 1));
  enhanced_.resize(n);
  for (std::size_t c = 0; c < rows.size(); ++c) {
    const auto row = rows[c];
    // The row's window sums from prefix sums in double (O(t) whatever the window).
    prefix_.assign(t + 1, 0.0);
    prefix2_.assign(t + 1, 0.0);
    for (std::size_t j = 0; j < t; ++j) {
      prefix_[j + 1] = prefix_[j] + row[j];
      prefix2_[j + 1] = prefix2_[j] + static_cast<double>(row[j]) * row[j];
    }
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t lo = j >= w ? j - w : 0;
      const std::size_t hi = std::min(t - 1, j + w);
      enhanced_[j] = similarity::contrast_score(row[j], prefix_[hi + 1] - prefix_[lo], prefix2_[hi + 1] - prefix2_[lo],
                                                static_cast<double>(hi - lo + 1));
    }
    // The column's last w + 1 values S(t', j), t' = t - w .. t (rows that have column j: t' > j).
    auto& ring = recent_[c];
    ring[t % (w + 1)].assign(row.begin(), row.end());
    const std::size_t oldest = t >= w ? t - w : 0;
    for (std::size_t j = 0; j < n; ++j) {
      double sum = 0, sum2 = 0;
      std::size_t count = 0;
      for (std::size_t r = std::max(oldest, j + 1); r <= t; ++r) {
        const float v = ring[r % (w + 1)][j];
        sum += v;
        sum2 += static_cast<double>(v) * v;
        ++count;
      }
      const float column = similarity::contrast_score(row[j], sum, sum2, static_cast<double>(count));
      out[j] += 0.5F * (enhanced_[j] + column);
    }
  }
  if (rows.size() > 1) {
    for (auto& v : out) v /= static_cast<float>(rows.size());
  }
}

}  // namespace seqtopo::mapping
