#pragma once
// Patch-normalised thumbnails, the descriptor of SeqSLAM (Milford & Wyeth 2012) and the usual baseline of
// sequence-based place recognition: the intensity image is reduced to a small thumbnail (area averaging),
// then every patch of patch x patch pixels is normalised to mean 0 and standard deviation 1, which removes
// most of the change in brightness and contrast between visits. Two thumbnails are compared by the mean
// absolute difference of their pixels (Distance::sad).
#include <vector>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::image {

struct PatchConfig {
  int width = 64;  // thumbnail size [pixels]; SeqSLAM's 64 x 32
  int height = 32;
  int patch = 8;  // side of the normalised patches [pixels]; patches at the right/bottom border may be smaller
};

// Values are rounded to multiples of 1/kPatchGrid within +-127/kPatchGrid (a step of 1/16 standard deviation,
// far below the ~1 between thumbnails of different places; |z| <= sqrt(63) < 127/16 in an 8 x 8 patch, so
// only larger patches can clip), which lets two thumbnails be compared exactly in 8-bit integer lanes
// (similarity/distance_matrix: 32 pixels an instruction instead of 4).
inline constexpr double kPatchGrid = 16.0;

// width * height values, row-major. A patch of constant intensity becomes all zeros. Throws
// std::invalid_argument on an empty image or a non-positive size.
std::vector<float> patch_thumbnail(const RgbImage& image, const PatchConfig& config = {});

}  // namespace seqtopo::image
