#pragma once
// PNG and JPEG encoding of plain RGB images (the only place besides image/ that links OpenCV's codecs).
#include <filesystem>
#include <string>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::plot {

std::string encode_png(const RgbImage& image);
// JPEG at `quality` (1..100): the report's thumbnails.
std::string encode_jpeg(const RgbImage& image, int quality = 80);
// The image reduced (area means) so that its larger side is at most max_side [pixels]; smaller ones unchanged.
RgbImage shrink(const RgbImage& image, int max_side);
// Atomic write (temp file + rename); throws InputError naming the path.
void write_png(const std::filesystem::path& path, const RgbImage& image);

}  // namespace seqtopo::plot
