#include "seqtopo/image/image_io.hpp"

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
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
