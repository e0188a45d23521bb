#include "seqtopo/image/joint_histogram.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace seqtopo::image {

namespace {

constexpr int kPad = JointHistogramConfig::window_radius;

template <std::size_t N>
void check_increasing(const std::array<int, N>& edges, const char* name) {
  for (std::size_t k = 0; k < N; ++k) {
    if (edges[k] < 0 || (k > 0 && edges[k] <= edges[k - 1])) {
      throw std::invalid_argument(std::string("joint histogram: ") + name + " must be non-negative and increasing");
    }
  }
}

// Copies a width x height plane into the centre of a (width + 2 pad) x (height + 2 pad) plane and
// replicates the border.
template <typename T>
void pad_replicate(const T* src, int width, int height, std::vector<T>& out) {
  const int pw = width + 2 * kPad;
  out.resize(static_cast<std::size_t>(pw) * static_cast<std::size_t>(height + 2 * kPad));
  for (int py = 0; py < height + 2 * kPad; ++py) {
    const int sy = std::clamp(py - kPad, 0, height - 1);
    const T* s = src + static_cast<std::ptrdiff_t>(sy) * width;
    T* d = out.data() + static_cast<std::ptrdiff_t>(py) * pw;
    std::fill(d, d + kPad, s[0]);
    std::copy(s, s + width, d + kPad);
    std::fill(d + kPad + width, d + pw, s[width - 1]);
  }
}

}  // namespace

void validate(const JointHistogramConfig& c) {
  check_increasing(c.gradient_edges, "gradient_edges");
  check_increasing(c.edge_density_edges, "edge_density_edges");
  check_increasing(c.texture_edges, "texture_edges");
  if (c.edge_threshold < 0 || c.texture_threshold < 0) {
    throw std::invalid_argument("joint histogram: thresholds must be non-negative");
  }
}

std::uint32_t joint_bin(int edge_count, std::int32_t gradient2, int texturedness, int rank, std::uint8_t r,
                        std::uint8_t g, std::uint8_t b, const JointHistogramConfig& c) {
  std::uint32_t e = 0, m = 0, t = 0;
  for (int edge : c.edge_density_edges) e += edge_count >= edge ? 1U : 0U;
  for (int edge : c.gradient_edges) m += gradient2 >= edge * edge ? 1U : 0U;
  for (int edge : c.texture_edges) t += texturedness >= edge ? 1U : 0U;
  const auto k = static_cast<std::uint32_t>(rank * 4 / 25);
  return (((((e * 5 + m) * 4 + t) * 4 + k) * 4 + (r >> 6U)) * 4 + (g >> 6U)) * 4 + (b >> 6U);
}

JointFeatures joint_features(const RgbImage& image, const JointHistogramConfig& c) {
  validate(c);
  const int w = image.width, h = image.height;
  if (w <= 0 || h <= 0 || image.pixels.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3) {
    throw std::invalid_argument("joint histogram: empty or malformed image");
  }
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const int pw = w + 2 * kPad;
  JointFeatures f;
  f.width = w;
  f.height = h;
  f.intensity.resize(n);
  f.gradient2.resize(n);
  f.edge_count.resize(n);
  f.texturedness.resize(n);
  f.rank.resize(n);
  f.bin.resize(n);

  const std::uint8_t* rgb = image.pixels.data();
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned v = 77U * rgb[3 * i] + 150U * rgb[3 * i + 1] + 29U * rgb[3 * i + 2] + 128U;
    f.intensity[i] = static_cast<std::uint8_t>(v >> 8U);
  }
  std::vector<std::uint8_t> p;  // padded intensity
  pad_replicate(f.intensity.data(), w, h, p);

  // Sobel and the edge map.
  const std::int32_t edge2 = c.edge_threshold * c.edge_threshold;
  std::vector<std::uint8_t> edges(n);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* up = p.data() + static_cast<std::ptrdiff_t>(y + kPad - 1) * pw + kPad;
    const std::uint8_t* mid = up + pw;
    const std::uint8_t* down = mid + pw;
    std::int32_t* g2 = f.gradient2.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::uint8_t* e = edges.data() + static_cast<std::ptrdiff_t>(y) * w;
#pragma omp simd
    for (int x = 0; x < w; ++x) {
      const std::int32_t gx = (up[x + 1] + 2 * mid[x + 1] + down[x + 1]) - (up[x - 1] + 2 * mid[x - 1] + down[x - 1]);
      const std::int32_t gy = (down[x - 1] + 2 * down[x] + down[x + 1]) - (up[x - 1] + 2 * up[x] + up[x + 1]);
      const std::int32_t m2 = gx * gx + gy * gy;
      g2[x] = m2;
      e[x] = m2 > edge2 ? 1 : 0;
    }
  }

  // Edge density: a separable 5x5 box sum over the padded edge map.
  std::vector<std::uint8_t> pe;
  pad_replicate(edges.data(), w, h, pe);
  std::vector<std::uint8_t> column(static_cast<std::size_t>(pw));
  for (int y = 0; y < h; ++y) {
    std::fill(column.begin(), column.end(), std::uint8_t{0});
    for (int dy = 0; dy <= 2 * kPad; ++dy) {
      const std::uint8_t* row = pe.data() + static_cast<std::ptrdiff_t>(y + dy) * pw;
#pragma omp simd
      for (int x = 0; x < pw; ++x)
        column[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(column[static_cast<std::size_t>(x)] + row[x]);
    }
    std::uint8_t* out = f.edge_count.data() + static_cast<std::ptrdiff_t>(y) * w;
#pragma omp simd
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* col = column.data() + x;
      out[x] = static_cast<std::uint8_t>(col[0] + col[1] + col[2] + col[3] + col[4]);
    }
  }

  // Texturedness (3x3) and rank (5x5): one pass per neighbour offset so each inner loop is a plain
  // element-wise comparison of two rows.
  const int tt = c.texture_threshold;
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* centre = p.data() + static_cast<std::ptrdiff_t>(y + kPad) * pw + kPad;
    std::uint8_t* tex = f.texturedness.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::uint8_t* rank = f.rank.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::fill(tex, tex + w, std::uint8_t{0});
    std::fill(rank, rank + w, std::uint8_t{0});
    for (int dy = -kPad; dy <= kPad; ++dy) {
      for (int dx = -kPad; dx <= kPad; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const std::uint8_t* other = centre + static_cast<std::ptrdiff_t>(dy) * pw + dx;
#pragma omp simd
        for (int x = 0; x < w; ++x) rank[x] = static_cast<std::uint8_t>(rank[x] + (other[x] < centre[x] ? 1 : 0));
        if (dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1) {
#pragma omp simd
          for (int x = 0; x < w; ++x) {
            const int d = static_cast<int>(other[x]) - static_cast<int>(centre[x]);
            tex[x] = static_cast<std::uint8_t>(tex[x] + ((d > tt || d < -tt) ? 1 : 0));
          }
        }
      }
    }
  }

  // Joint bin per pixel.
  const auto& ge = c.gradient_edges;
  const auto& de = c.edge_density_edges;
  const auto& te = c.texture_edges;
  const std::int32_t g0 = ge[0] * ge[0], g1 = ge[1] * ge[1], g2e = ge[2] * ge[2], g3 = ge[3] * ge[3];
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    const int cnt = f.edge_count[i], tx = f.texturedness[i];
    const std::int32_t m2 = f.gradient2[i];
    const unsigned e = (cnt >= de[0] ? 1U : 0U) + (cnt >= de[1] ? 1U : 0U) + (cnt >= de[2] ? 1U : 0U);
    const unsigned m = (m2 >= g0 ? 1U : 0U) + (m2 >= g1 ? 1U : 0U) + (m2 >= g2e ? 1U : 0U) + (m2 >= g3 ? 1U : 0U);
    const unsigned t = (tx >= te[0] ? 1U : 0U) + (tx >= te[1] ? 1U : 0U) + (tx >= te[2] ? 1U : 0U);
    const unsigned k = static_cast<unsigned>(f.rank[i]) * 4U / 25U;
    const unsigned r = rgb[3 * i] >> 6U, g = rgb[3 * i + 1] >> 6U, b = rgb[3 * i + 2] >> 6U;
    f.bin[i] = static_cast<std::uint16_t>((((((e * 5 + m) * 4 + t) * 4 + k) * 4 + r) * 4 + g) * 4 + b);
  }
  return f;
}

similarity::SparseHistogram joint_histogram(const RgbImage& image, const JointHistogramConfig& config) {
  const JointFeatures f = joint_features(image, config);
  std::vector<std::uint32_t> counts(JointHistogramConfig::bins, 0);
  for (std::uint16_t b : f.bin) ++counts[b];
  similarity::SparseHistogram h;
  h.dimension = JointHistogramConfig::bins;
  const float scale = 1.0F / static_cast<float>(f.bin.size());
  for (std::uint32_t k = 0; k < JointHistogramConfig::bins; ++k) {
    if (counts[k] == 0) continue;
    h.bins.push_back(k);
    h.values.push_back(static_cast<float>(counts[k]) * scale);
  }
  return h;
}

}  // namespace seqtopo::image
