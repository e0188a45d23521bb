#pragma once
// The joint histogram of Pass & Zabih ("Comparing images using joint histograms", 1999), the image
// descriptor of the mapping paper (section IV-A): every pixel gets seven local features, each feature is
// quantised, and the histogram counts pixels per combination of the seven quantised values.
//
// Features, all computed on the 8-bit intensity I = (77 R + 150 G + 29 B + 128) >> 8 (BT.601 luma in
// integers) with borders replicated (a pixel outside the image takes the value of the nearest one inside):
//
//   gradient magnitude  Sobel 3x3: gx, gy in [-1020, 1020]; the magnitude m = sqrt(gx^2 + gy^2) is a
//                        Sobel response, 8x the intensity step per pixel of a linear ramp. Bins (5):
//                        m < 16 | < 48 | < 120 | < 320 | >= 320, i.e. steps of about 2, 6, 15 and 40
//                        grey levels per pixel: flat, noise and soft shading, weak edges, edges, strong edges.
//                        Sobel rather than a 2-tap difference because it smooths across the edge, so JPEG
//                        noise stays in the lowest bins.
//   edge density         the pixel is an edge when m > edge_threshold (96: a step of 12 grey levels per
//                        pixel, above JPEG noise and below the contrast of door frames). The paper's source
//                        uses an edge detector; a thresholded Sobel is used instead of Canny because Canny's
//                        hysteresis and thinning are not local and would make the feature depend on pixels
//                        far away. Density = edge pixels in the 5x5 window around the pixel (0..25). Bins (4):
//                        0 | 1..5 | 6..11 | 12..25: flat, near one edge (a thin edge crosses 5 cells of the
//                        window, a Sobel edge is ~2 pixels wide), on an edge or corner, in dense texture.
//   texturedness         the number of 8-neighbours whose intensity differs from the pixel's by more than
//                        texture_threshold (8 grey levels: above the noise of compressed images) (0..8).
//                        Bins (4): 0 | 1..2 | 3..5 | 6..8.
//   rank                 the number of pixels in the 5x5 window strictly darker than the pixel (0..24): a
//                        contrast-invariant local brightness. Bins (4): floor(rank * 4 / 25), i.e.
//                        0..6 | 7..12 | 13..18 | 19..24.
//   R, G, B              floor(value / 64): 4 equal bins per channel (0..63 | 64..127 | 128..191 | 192..255).
//
// Bin counts 4, 5, 4, 4, 4, 4, 4 are those of the paper: 20,480 bins. The bin index is
//   ((((((edge_density * 5 + gradient) * 4 + texturedness) * 4 + rank) * 4 + R) * 4 + G) * 4 + B
// and the histogram is normalised to sum 1 (count / pixels), so images of different sizes compare.
// Window sizes (3x3 Sobel and texturedness, 5x5 density and rank) are fixed: they set the scale of "local"
// for images of a few hundred pixels across, the size of the paper's 320x240 images.
#include <array>
#include <cstdint>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/similarity/sparse_histogram.hpp"

namespace seqtopo::image {

struct JointHistogramConfig {
  // Sobel magnitude bin edges, increasing: bin g holds gradient_edges[g-1] <= m < gradient_edges[g].
  std::array<int, 4> gradient_edges{16, 48, 120, 320};
  int edge_threshold = 96;                          // edge pixel: Sobel magnitude m > this
  std::array<int, 3> edge_density_edges{1, 6, 12};  // bin e holds counts >= edges[e-1] and < edges[e]
  int texture_threshold = 8;                        // neighbour counts when |I_n - I| > this [grey levels]
  std::array<int, 3> texture_edges{1, 3, 6};        // bins of the texturedness count, as for edge density

  static constexpr int edge_density_bins = 4, gradient_bins = 5, texture_bins = 4, rank_bins = 4, colour_bins = 4;
  static constexpr std::uint32_t bins = 4 * 5 * 4 * 4 * 4 * 4 * 4;  // 20,480
  static constexpr int window_radius = 2;                           // 5x5 windows for edge density and rank
};

// Every per-pixel feature, row-major, width * height each (exposed for tests and plots).
struct JointFeatures {
  int width = 0, height = 0;
  std::vector<std::uint8_t> intensity;
  std::vector<std::int32_t> gradient2;     // squared Sobel magnitude gx^2 + gy^2
  std::vector<std::uint8_t> edge_count;    // edge pixels in the 5x5 window, 0..25
  std::vector<std::uint8_t> texturedness;  // 0..8
  std::vector<std::uint8_t> rank;          // 0..24
  std::vector<std::uint16_t> bin;          // joint bin index, < JointHistogramConfig::bins
};

// Throws std::invalid_argument when the edges are not increasing or thresholds are negative.
void validate(const JointHistogramConfig& config);

// The bin of one pixel from its raw feature values.
std::uint32_t joint_bin(int edge_count, std::int32_t gradient2, int texturedness, int rank, std::uint8_t r,
                        std::uint8_t g, std::uint8_t b, const JointHistogramConfig& config = {});

JointFeatures joint_features(const RgbImage& image, const JointHistogramConfig& config = {});

// The normalised joint histogram (sum 1), non-empty bins only. Throws std::invalid_argument on an empty image.
similarity::SparseHistogram joint_histogram(const RgbImage& image, const JointHistogramConfig& config = {});

}  // namespace seqtopo::image
