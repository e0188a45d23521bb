// libseqtopo_codecs.so: OpenCV's imgcodecs and videoio behind the table of codec_table.hpp, loaded by
// src/image/codecs.cpp when the first image is decoded or encoded.
#include <dlfcn.h>

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "codec_table.hpp"

namespace {

using seqtopo::image::codecs::CodecTable;
using seqtopo::image::codecs::VideoProperty;

bool decode(const std::uint8_t* data, std::size_t size, cv::Mat* out) {
  try {
    const cv::Mat bytes(1, static_cast<int>(size), CV_8U, const_cast<std::uint8_t*>(data));
    *out = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    return !out->empty();
  } catch (...) {
    out->release();
    return false;
  }
}

bool read_grey(const char* path, cv::Mat* out) {
  try {
    *out = cv::imread(path, cv::IMREAD_GRAYSCALE);
    return !out->empty();
  } catch (...) {
    out->release();
    return false;
  }
}

bool encode(const char* extension, const cv::Mat* image, int jpeg_quality, std::vector<std::uint8_t>* out) {
  try {
    const std::string ext(extension);
    return cv::imencode(ext, *image, *out,
                        ext == ".jpg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, jpeg_quality} : std::vector<int>{});
  } catch (...) {
    return false;
  }
}

void* video_open(const char* path) {
  auto* capture = new cv::VideoCapture;
  try {
    if (!capture->open(path, cv::CAP_FFMPEG)) capture->open(path, cv::CAP_GSTREAMER);
  } catch (...) {
  }
  if (!capture->isOpened()) {
    delete capture;
    return nullptr;
  }
  return capture;
}

double video_property(void* video, VideoProperty property) {
  const int id = property == VideoProperty::frame_count   ? cv::CAP_PROP_FRAME_COUNT
                 : property == VideoProperty::frame_width ? cv::CAP_PROP_FRAME_WIDTH
                                                          : cv::CAP_PROP_FRAME_HEIGHT;
  try {
    return static_cast<cv::VideoCapture*>(video)->get(id);
  } catch (...) {
    return 0;
  }
}

bool video_grab(void* video) {
  try {
    return static_cast<cv::VideoCapture*>(video)->grab();
  } catch (...) {
    return false;
  }
}

bool video_retrieve(void* video, cv::Mat* frame) {
  try {
    return static_cast<cv::VideoCapture*>(video)->retrieve(*frame) && !frame->empty();
  } catch (...) {
    frame->release();
    return false;
  }
}

void video_close(void* video) { delete static_cast<cv::VideoCapture*>(video); }

}  // namespace

// libpng's default handlers print "libpng warning: iCCP: known incorrect sRGB profile" (and "libpng error: ...")
// on stderr, and OpenCV's PNG decoder installs none of its own: the one line of an error, or the progress, would
// be interleaved with them. This plugin defines png_create_read_struct, found before libpng16's by the
// decoder's lookup (the plugin precedes its dependencies in the dlopen'd scope), and passes silent handlers on;
// a decoding error still ends in libpng's longjmp, and OpenCV reports it as an image that does not decode.
extern "C" {
using PngStruct = void*;
using PngHandler = void (*)(PngStruct, const char*);
using PngCreate = PngStruct (*)(const char*, void*, PngHandler, PngHandler);
using PngLongjmp = void (*)(PngStruct, int);

__attribute__((visibility("default"))) PngStruct png_create_read_struct(const char* version, void* error_ptr,
                                                                        PngHandler error_fn, PngHandler warn_fn) {
  static const auto real = reinterpret_cast<PngCreate>(dlsym(RTLD_NEXT, "png_create_read_struct"));
  static const auto jump = reinterpret_cast<PngLongjmp>(dlsym(RTLD_NEXT, "png_longjmp"));
  if (real == nullptr) return nullptr;
  const PngHandler silent_error = [](PngStruct png, const char*) {
    if (jump) jump(png, 1);
    std::abort();  // libpng's contract: an error handler does not return
  };
  const PngHandler silent_warning = [](PngStruct, const char*) {};
  return real(version, error_ptr, error_fn != nullptr || jump == nullptr ? error_fn : silent_error,
              warn_fn != nullptr ? warn_fn : silent_warning);
}
}

extern "C" const CodecTable* seqtopo_codec_table() {
  static const CodecTable table{seqtopo::image::codecs::kCodecTableVersion,
                                decode,
                                read_grey,
                                encode,
                                video_open,
                                video_property,
                                video_grab,
                                video_retrieve,
                                video_close};
  return &table;
}
