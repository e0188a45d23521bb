#pragma once
// PNG and JPEG through libpng and libjpeg-turbo themselves, for codecs.cpp: the formats seqtopo meets at every
// run decode and encode without opening the OpenCV plugin. Each decode makes the library calls OpenCV 4.6's
// decoders make (same libraries, same transforms), so it gives the pixels imdecode(IMREAD_UNCHANGED) and
// imread(IMREAD_GRAYSCALE) give; what is not certain to match is left to the plugin (Outcome::unhandled).
// Internal to the image module (and its tests): not installed.
#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

namespace seqtopo::image::codecs::direct {

enum class Mode {
  unchanged,  // OpenCV's IMREAD_UNCHANGED: the stored channels (BGR order) and depth
  grey,       // OpenCV's IMREAD_GRAYSCALE: 8-bit grey
};

enum class Outcome {
  decoded,
  failed,     // OpenCV's decoder fails on the same bytes (out is empty)
  unhandled,  // not PNG or JPEG, or a variant left to the plugin
};

Outcome decode(std::span<const std::uint8_t> bytes, Mode mode, cv::Mat& out);

// 8-bit grey or BGR; throw std::runtime_error otherwise or when the library fails. Deterministic bytes.
std::vector<std::uint8_t> encode_png(const cv::Mat& image);
// quality 1-100; progressive for the tests' progressive files.
std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality, bool progressive = false);

}  // namespace seqtopo::image::codecs::direct
