#include "seqtopo/image/image_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/image/codecs.hpp"

namespace seqtopo::image {

namespace fs = std::filesystem;

namespace {

RgbImage to_rgb(const cv::Mat& decoded) {
  cv::Mat eight;
  if (decoded.depth() == CV_8U) {
    eight = decoded;
  } else if (decoded.depth() == CV_16U) {
    decoded.convertTo(eight, CV_8U, 1.0 / 257.0);
  } else {
    decoded.convertTo(eight, CV_8U);
  }
  cv::Mat rgb;
  switch (eight.channels()) {
    case 1:
      cv::cvtColor(eight, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(eight, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(eight, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      throw std::invalid_argument("unsupported number of channels");
  }
  RgbImage out(rgb.cols, rgb.rows);
  for (int y = 0; y < rgb.rows; ++y) {
    const auto* src = rgb.ptr<std::uint8_t>(y);
    std::copy(src, src + static_cast<std::ptrdiff_t>(rgb.cols) * 3, out.at(0, y));
  }
  return out;
}

// A JPEG that stops before its end-of-image marker decodes to a partly grey picture with only a warning;
// such a file is reported as corrupt instead of silently compared.
bool truncated_jpeg(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return false;
  std::size_t end = bytes.size();
  while (end > 2 && (bytes[end - 1] == 0x00 || bytes[end - 1] == 0x0A || bytes[end - 1] == 0x0D)) --end;  // padding
  return !(bytes[end - 2] == 0xFF && bytes[end - 1] == 0xD9);
}

void quiet_opencv() {
  static const bool once = [] {
    // Every failure becomes an InputError naming the file, so the library's own reports are noise.
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    ::setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET, unless the user asked for something else
    return true;
  }();
  (void)once;
}

}  // namespace

namespace {

std::uint32_t big_endian(const std::uint8_t* p, int bytes) {
  std::uint32_t v = 0;
  for (int k = 0; k < bytes; ++k) v = (v << 8U) | p[k];
  return v;
}
std::uint32_t little_endian(const std::uint8_t* p, int bytes) {
  std::uint32_t v = 0;
  for (int k = bytes - 1; k >= 0; --k) v = (v << 8U) | p[k];
  return v;
}

std::optional<ImageHeader> valid(ImageHeader h) {
  if (h.width <= 0 || h.height <= 0) return std::nullopt;
  return h;
}

// JPEG: the first start-of-frame marker (SOF0-SOF15 but DHT, JPG and DAC) after the segments before it.
std::optional<ImageHeader> jpeg_header(std::ifstream& in) {
  std::array<std::uint8_t, 8> b{};
  in.seekg(2);
  for (int segments = 0; segments < 10000 && in; ++segments) {
    int marker = in.get();
    if (marker != 0xFF) return std::nullopt;
    while (marker == 0xFF) marker = in.get();  // fill bytes
    if (marker == EOF) return std::nullopt;
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // no length
    if (!in.read(reinterpret_cast<char*>(b.data()), 2)) return std::nullopt;
    const std::uint32_t length = big_endian(b.data(), 2);
    if (length < 2) return std::nullopt;
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (length < 8 || !in.read(reinterpret_cast<char*>(b.data()), 6)) return std::nullopt;
      const int components = b[5];
      return valid({static_cast<int>(big_endian(b.data() + 3, 2)), static_cast<int>(big_endian(b.data() + 1, 2)),
                    components == 1 ? 1 : 3, 1});
    }
    in.seekg(static_cast<std::streamoff>(length - 2), std::ios::cur);
  }
  return std::nullopt;
}

// PNM: "P1".."P6", then width, height and (but for bitmaps) the largest value, with # comments between.
std::optional<ImageHeader> pnm_header(std::ifstream& in, char kind) {
  in.seekg(2);
  const auto number = [&]() -> long {
    for (int c = in.peek(); c != EOF; c = in.peek()) {
      if (c == '#') {
        std::string comment;
        std::getline(in, comment);
      } else if (std::isspace(c) != 0) {
        in.get();
      } else {
        break;
      }
    }
    long v = -1;
    if (!(in >> v)) return -1;
    return v;
  };
  const long w = number(), h = number();
  const long max = kind == '1' || kind == '4' ? 1 : number();
  if (w <= 0 || h <= 0 || max <= 0 || w > INT32_MAX || h > INT32_MAX) return std::nullopt;
  const bool grey = kind == '1' || kind == '2' || kind == '4' || kind == '5';
  return valid({static_cast<int>(w), static_cast<int>(h), grey ? 1 : 3, max > 255 ? 2 : 1});
}

}  // namespace

std::optional<ImageHeader> read_image_header(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<std::uint8_t, 32> b{};
  if (!in || !in.read(reinterpret_cast<char*>(b.data()), b.size())) {
    if (!in.eof() || in.gcount() < 8) return std::nullopt;
    in.clear();
  }
  static constexpr std::array<std::uint8_t, 8> kPng{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (std::equal(kPng.begin(), kPng.end(), b.begin())) {
    // IHDR first: width, height, bit depth, colour type (0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA)
    if (std::memcmp(b.data() + 12, "IHDR", 4) != 0) return std::nullopt;
    const int depth = b[24], colour = b[25];
    return valid({static_cast<int>(big_endian(b.data() + 16, 4)), static_cast<int>(big_endian(b.data() + 20, 4)),
                  colour == 0   ? 1
                  : colour == 2 ? 3
                                : 4,
                  depth == 16 ? 2 : 1});
  }
  if (b[0] == 0xFF && b[1] == 0xD8) return jpeg_header(in);
  if (b[0] == 'B' && b[1] == 'M') {
    const std::uint32_t info = little_endian(b.data() + 14, 4);
    if (info == 12) {  // OS/2 core header: 16-bit sizes
      return valid(
          {static_cast<int>(little_endian(b.data() + 18, 2)), static_cast<int>(little_endian(b.data() + 20, 2)), 3, 1});
    }
    const auto height = static_cast<std::int32_t>(little_endian(b.data() + 22, 4));
    const int bits = static_cast<int>(little_endian(b.data() + 28, 2));
    return valid(
        {static_cast<int>(little_endian(b.data() + 18, 4)), height < 0 ? -height : height, bits == 32 ? 4 : 3, 1});
  }
  if (b[0] == 'P' && b[1] >= '1' && b[1] <= '6') return pnm_header(in, static_cast<char>(b[1]));
  if (std::memcmp(b.data(), "RIFF", 4) == 0 && std::memcmp(b.data() + 8, "WEBP", 4) == 0) {
    const std::uint8_t* chunk = b.data() + 12;
    if (std::memcmp(chunk, "VP8X", 4) == 0) {  // canvas size - 1, 24 bits each
      return valid({static_cast<int>(little_endian(b.data() + 24, 3)) + 1,
                    static_cast<int>(little_endian(b.data() + 27, 3)) + 1, 4, 1});
    }
    if (std::memcmp(chunk, "VP8L", 4) == 0 && b[20] == 0x2F) {  // 14 bits each of width - 1 and height - 1
      const std::uint32_t bits = little_endian(b.data() + 21, 4);
      return valid({static_cast<int>(bits & 0x3FFFU) + 1, static_cast<int>((bits >> 14U) & 0x3FFFU) + 1, 4, 1});
    }
    if (std::memcmp(chunk, "VP8 ", 4) == 0 && b[23] == 0x9D && b[24] == 0x01 && b[25] == 0x2A) {
      return valid({static_cast<int>(little_endian(b.data() + 26, 2) & 0x3FFFU),
                    static_cast<int>(little_endian(b.data() + 28, 2) & 0x3FFFU), 3, 1});
    }
  }
  return std::nullopt;
}

ImageHeader image_size(const fs::path& path) {
  if (const auto header = read_image_header(path)) return *header;
  const RgbImage decoded = load_image(path);
  return ImageHeader{decoded.width, decoded.height, 3, 1};
}

std::size_t decode_peak_bytes(const ImageHeader& h, std::size_t file_bytes) {
  const std::size_t pixels = static_cast<std::size_t>(h.width) * static_cast<std::size_t>(h.height);
  const auto channels = static_cast<std::size_t>(h.channels);
  const std::size_t decoded = pixels * channels * static_cast<std::size_t>(h.bytes_per_sample);
  const std::size_t eight = h.bytes_per_sample > 1 ? pixels * channels : 0;
  return file_bytes + decoded + eight + 2 * 3 * pixels;  // + the RGB Mat and the RgbImage
}

RgbImage decode_image(std::span<const std::uint8_t> bytes, const std::string& subject) {
  quiet_opencv();
  if (bytes.empty()) throw InputError(subject, "empty, not an image");
  if (truncated_jpeg(bytes)) throw InputError(subject, "corrupt image (truncated JPEG)");
  const cv::Mat decoded = codecs::decode(bytes);
  if (decoded.empty() || decoded.cols <= 0 || decoded.rows <= 0) {
    throw InputError(subject, "cannot decode image (corrupt or unsupported format)");
  }
  try {
    return to_rgb(decoded);
  } catch (const std::exception& e) {
    throw InputError(subject, std::string("cannot convert image: ") + e.what());
  }
}

RgbImage load_image(const fs::path& path) {
  require_regular_file(path, "image");  // /dev/zero or a FIFO would be read forever
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open image");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw InputError(path.string(), "empty file, not an image");
  return decode_image(bytes, path.string());
}

namespace {

codecs::Video open_video(const fs::path& path) {
  quiet_opencv();
  require_regular_file(path, "video file");  // /dev/zero or a FIFO would be read forever
  codecs::Video capture(path);
  if (!capture.opened()) throw InputError(path.string(), "cannot open as a video (corrupt or unsupported format)");
  return capture;
}

// The frames an open video's container announces, when it gives a plausible count.
std::optional<std::size_t> announced_frames(const codecs::Video& capture) {
  const double n = capture.frame_count();
  if (!(n > 0) || n > 1e12) return std::nullopt;
  return static_cast<std::size_t>(n);
}

}  // namespace

std::optional<std::size_t> video_frame_count(const fs::path& path) { return announced_frames(open_video(path)); }

std::optional<ImageHeader> video_frame_header(const fs::path& path) {
  const codecs::Video capture = open_video(path);
  return valid(ImageHeader{capture.frame_width(), capture.frame_height(), 3, 1});
}

VideoFrames for_each_video_frame(const fs::path& path, std::size_t every,
                                 const std::function<void(std::size_t, const RgbImage&)>& visit) {
  if (every == 0) throw std::invalid_argument("--every must be at least 1");
  codecs::Video capture = open_video(path);
  VideoFrames frames;
  frames.announced = announced_frames(capture);
  std::size_t index = 0, kept = 0;
  cv::Mat frame;
  while (capture.grab()) {
    if (index % every == 0) {
      if (!capture.retrieve(frame) || frame.empty()) {
        throw InputError(path.string(), "cannot decode frame " + std::to_string(index));
      }
      visit(index, to_rgb(frame));
      ++kept;
    }
    ++index;
  }
  if (kept == 0) throw InputError(path.string(), "video holds no frame");
  frames.read = index;
  return frames;
}

std::string video_ended_early(const fs::path& path, const VideoFrames& frames) {
  if (!frames.announced) return {};
  const auto announced = static_cast<double>(*frames.announced), read = static_cast<double>(frames.read);
  if (read >= 0.98 * announced - 1) return {};
  return "warning: " + path.string() + ": the video ended after " + std::to_string(frames.read) + " of the " +
         std::to_string(*frames.announced) + " frames it announces (truncated or damaged?); only those are mapped";
}

}  // namespace seqtopo::image
