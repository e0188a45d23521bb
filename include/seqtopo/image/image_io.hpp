#pragma once
// Reading images and video frames into plain RGB images (OpenCV stays behind this header).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::image {

// Decodes one image file (colour or grey, 8 or 16 bit) to 8-bit RGB. Throws InputError naming the file
// when it is missing, unreadable, corrupt or not an image.
RgbImage load_image(const std::filesystem::path& path);

// Decodes an encoded image held in memory (PNG, JPEG, ... as in a ROS CompressedImage message) to 8-bit
// RGB, with the same conversions as load_image. Throws InputError naming `subject` when the bytes are not
// a decodable image.
RgbImage decode_image(std::span<const std::uint8_t> bytes, const std::string& subject);

// An image's size as its file's header gives it, without decoding: what load_image will hold of it.
struct ImageHeader {
  int width = 0, height = 0;
  int channels = 3;          // as the decoder gives them (alpha included, a palette expanded)
  int bytes_per_sample = 1;  // 2 for 16-bit images
};

// Reads the header of a PNG, JPEG, BMP, PNM or WebP file (the dimensions lie at fixed places of each; OpenCV has no
// call that reads them without decoding). std::nullopt for another format or a header it cannot read.
std::optional<ImageHeader> read_image_header(const std::filesystem::path& path);

// read_image_header's answer, or for another format the size of the image decoded once. Throws InputError naming
// the file when it cannot be decoded.
ImageHeader image_size(const std::filesystem::path& path);

// The bytes load_image holds at its peak for an image of this header and `file_bytes` encoded: the file read,
// the decoded picture, its 8-bit copy (16-bit images), the RGB conversion and the RgbImage returned.
std::size_t decode_peak_bytes(const ImageHeader& header, std::size_t file_bytes);

// Frames the container announces (may be approximate or missing for some formats); throws InputError
// naming the file when it cannot be opened as a video.
std::optional<std::size_t> video_frame_count(const std::filesystem::path& path);

// A video's frame size as its stream announces it (std::nullopt when it does not), without decoding a frame;
// throws InputError naming the file when it cannot be opened as a video.
std::optional<ImageHeader> video_frame_header(const std::filesystem::path& path);

// The frames a pass over a video read, and those its container announced (when it did).
struct VideoFrames {
  std::size_t read = 0;
  std::optional<std::size_t> announced;
};

// Calls `visit(frame_index, image)` for frames 0, every, 2 * every, ... in order. Throws InputError
// naming the file when it cannot be opened or yields no frame, std::invalid_argument when every == 0.
VideoFrames for_each_video_frame(const std::filesystem::path& path, std::size_t every,
                                 const std::function<void(std::size_t, const RgbImage&)>& visit);

// A warning line when the video ended clearly before the frames its container announced (a truncated or
// damaged file, whose frames read are all a run gets), else "". The announced count may be approximate, so a
// shortfall of up to 2 % (and 1 frame) is not one.
std::string video_ended_early(const std::filesystem::path& path, const VideoFrames& frames);

}  // namespace seqtopo::image
