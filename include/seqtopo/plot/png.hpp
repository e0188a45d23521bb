#pragma once
// PNG encoding of plain RGB images (the only place besides image/ that links OpenCV's codecs).
#include <filesystem>
#include <string>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::plot {

std::string encode_png(const RgbImage& image);
// Atomic write (temp file + rename); throws InputError naming the path.
void write_png(const std::filesystem::path& path, const RgbImage& image);

}  // namespace seqtopo::plot
