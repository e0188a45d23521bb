// libFuzzer harness: PNG and JPEG decoded by libpng and libjpeg-turbo themselves (src/image/png_jpeg.hpp), whose
// errors unwind through setjmp/longjmp. A failure is an empty Mat, a variant left to OpenCV's plugin is
// "unhandled"; anything else (an exception, a sanitizer report, a Mat that is not what it says) is a finding.
// What decodes as 8-bit grey or BGR is encoded as PNG and decoded back to the same pixels.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "png_jpeg.hpp"

namespace {

using seqtopo::image::codecs::direct::Mode;
using seqtopo::image::codecs::direct::Outcome;

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::countNonZero(a.reshape(1) != b.reshape(1)) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace direct = seqtopo::image::codecs::direct;
  for (const Mode mode : {Mode::unchanged, Mode::grey}) {
    cv::Mat image;
    const Outcome outcome = direct::decode(std::span(data, size), mode, image);
    if (outcome != Outcome::decoded) {
      if (outcome == Outcome::failed && !image.empty()) std::abort();
      continue;
    }
    if (image.empty() || image.rows <= 0 || image.cols <= 0) std::abort();
    if (mode == Mode::grey && image.type() != CV_8UC1) std::abort();
    if (image.type() != CV_8UC1 && image.type() != CV_8UC3) continue;
    cv::Mat again;
    if (direct::decode(direct::encode_png(image), Mode::unchanged, again) != Outcome::decoded || !same(image, again))
      std::abort();
  }
  return 0;
}
