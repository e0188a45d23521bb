#pragma once
// What libseqtopo_codecs.so gives the image module (seqtopo/image/codecs.hpp): its seqtopo_codec_table()
// returns this table. Both sides are compiled from this header in one build and share libopencv_core, so
// cv::Mat crosses over as it is; no exception does (every entry reports failure by its result).
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace seqtopo::image::codecs {

inline constexpr int kCodecTableVersion = 2;

// What a video's container or stream announces (this side does not include OpenCV's videoio).
enum class VideoProperty { frame_count, frame_width, frame_height };

struct CodecTable {
  int version;
  bool (*decode)(const std::uint8_t* data, std::size_t size, cv::Mat* out);
  bool (*read_grey)(const char* path, cv::Mat* out);
  // extension ".png" or ".jpg"; jpeg_quality 1-100 for ".jpg"
  bool (*encode)(const char* extension, const cv::Mat* image, int jpeg_quality, std::vector<std::uint8_t>* out);
  void* (*video_open)(const char* path);                          // nullptr when it cannot be opened
  double (*video_property)(void* video, VideoProperty property);  // 0 when the video does not say
  bool (*video_grab)(void* video);
  bool (*video_retrieve)(void* video, cv::Mat* frame);
  void (*video_close)(void* video);
};

}  // namespace seqtopo::image::codecs

extern "C" const seqtopo::image::codecs::CodecTable* seqtopo_codec_table();
