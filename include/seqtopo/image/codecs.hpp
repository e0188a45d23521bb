#pragma once
// OpenCV's image and video codecs, loaded when first needed. Debian's imgcodecs and videoio bring about 250
// shared libraries with them (GDAL, GDCM, GStreamer, FFmpeg, ...): linked into a program they cost every start
// of it 0.3 s in the dynamic loader (a second under AddressSanitizer), `--help` as much as a map. So they live
// in a plugin, libseqtopo_codecs.so (src/image/plugin/). PNG and JPEG, met at every run (frames, the figures
// of every map), are decoded and encoded by libpng and libjpeg-turbo linked in (src/image/png_jpeg.cpp): the
// same pixels as OpenCV's decoders, which make the same library calls. The plugin opens at the first other
// format, PNG or JPEG variant left to OpenCV (CMYK, a grey read of an Exif image), or video.
//
// The plugin is looked for in this order: the file $SEQTOPO_CODECS names (then nowhere else); beside the
// program or shared library holding this code, and beside the running program (the Python package, the
// build tree's seqtopo-main), or in the lib/ folder two levels up (seqtopo-main installed in libexec/seqtopo/);
// the build tree it was built in; the library folder it was installed to; the dynamic loader's search path. When it
// cannot be loaded every call throws std::runtime_error saying where it looked and why it failed.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

namespace seqtopo::image::codecs {

// Loads the plugin now rather than at its first use (a run that measures its own memory first, for one);
// throws std::runtime_error when it cannot be loaded.
void load();

// Whether an image file is read without the plugin, told by its name: PNG and JPEG (.png, .jpg, .jpeg in any case).
// Other formats open it (and an unusual PNG or JPEG may still be left to it).
bool read_without_plugin(const std::filesystem::path& file);

// The image as stored (OpenCV's IMREAD_UNCHANGED); empty when OpenCV cannot decode the bytes.
cv::Mat decode(std::span<const std::uint8_t> bytes);

// The file read as 8-bit grey; empty when it cannot be read as an image.
cv::Mat read_grey(const std::filesystem::path& path);

// PNG, and JPEG of quality 1-100, of an 8-bit grey or BGR image (deterministic bytes, readable by OpenCV).
// Throws std::runtime_error for another image or when the library fails.
std::vector<std::uint8_t> encode_png(const cv::Mat& image);
std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality);

// A video file read frame by frame, by OpenCV's FFmpeg back-end or else its GStreamer one (file back-ends
// only: probing the camera back-ends with a file name is slow and leaks inside them).
class Video {
 public:
  explicit Video(const std::filesystem::path& path);
  ~Video();
  Video(Video&& other) noexcept;  // returned by value; never assigned
  Video(const Video&) = delete;
  Video& operator=(const Video&) = delete;

  bool opened() const { return handle_ != nullptr; }
  double frame_count() const;  // as the container announces it; 0 or less when it does not
  int frame_width() const;     // as the stream announces it; 0 when it does not
  int frame_height() const;
  bool grab();  // the next frame; false at the end
  bool retrieve(cv::Mat& frame);

 private:
  void* handle_ = nullptr;
};

}  // namespace seqtopo::image::codecs
