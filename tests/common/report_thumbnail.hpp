#pragma once
// The data URI the report embeds for an image at a thumbnail side: the image decoded, shrunk and JPEG-encoded as
// the report's thumbnails are (quality 75), for tests that look for an image in a report.
#include <filesystem>
#include <string>

#include "seqtopo/image/image_io.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::test_support {

inline std::string thumbnail_uri(const std::filesystem::path& image_file, int side) {
  const auto image = image::load_image(image_file);
  return "data:image/jpeg;base64," + report::base64(plot::encode_jpeg(plot::shrink(image, side), 75));
}

}  // namespace seqtopo::test_support
