#include "seqtopo/pipeline/session_input.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/pose_files.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/timeline/timed_poses.hpp"
#ifdef SEQTOPO_HAVE_RECORDING
#include "seqtopo/recording/recording.hpp"
#endif

namespace seqtopo::pipeline {

namespace fs = std::filesystem;

namespace {

// Up to this many rows (256 MiB of float32) a square descriptors.npy is read once more to see if it is symmetric.
constexpr std::size_t kSymmetryCheckRows = 8192;

// The number a file name's stem is, when it is one ("1403636579763555584.png", "12.5.jpg").
std::optional<double> number_name(const fs::path& file) {
  const std::string stem = file.stem().string();
  double v = 0;
  const auto [ptr, ec] = std::from_chars(stem.data(), stem.data() + stem.size(), v);
  if (stem.empty() || ec != std::errc() || ptr != stem.data() + stem.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::optional<std::vector<double>> frame_times(const SequenceInput& input, const fs::path& times) {
  // A times file has a line per frame of the video or image of the folder; the listing is already thinned.
  if (!times.empty()) return every_kth(formats::read_times_txt(times), input.every);
  const InputKind kind = resolve_input_kind(input);
  if (kind != InputKind::images) return std::nullopt;
  std::error_code ec;
  if (fs::exists(input.path / "times.txt", ec)) {
    return every_kth(formats::read_times_txt(input.path / "times.txt"), input.every);
  }
  const ImageListing listing = list_input_images(input);
  std::vector<double> out;
  for (const auto& f : listing.files) {
    const auto t = number_name(f);
    if (!t) return std::nullopt;
    out.push_back(*t);
  }
  const bool nanoseconds = !out.empty() && out.front() > 1e15;
  for (auto& t : out) t = nanoseconds ? t * 1e-9 : t;
  try {
    timeline::check_increasing(out);
  } catch (const std::invalid_argument& e) {
    throw InputError(input.path.string(), std::string("image times from the file names: ") + e.what());
  }
  return out;
}

PreparedSession prepare_session(const SessionSource& source) {
  PreparedSession s;
  s.input = source.input;
  s.input.frames.clear();
  const SequenceInput& input = s.input;
  const InputKind kind = resolve_input_kind(input);
  if (input.every == 0) throw InputError("--every", "must be at least 1");
  if (kind != InputKind::bag && !source.odometry_topic.empty() && source.odometry_topic != "none") {
    throw InputError("--odometry-topic", "needs a bag input, got " + input.path.string());
  }

  // The number of frames after `every`, where it is known without decoding.
  std::optional<std::size_t> count;
  if (kind == InputKind::images) {
    s.input.listing = std::make_shared<const ImageListing>(list_input_images(input));
    count = s.input.listing->files.size();
  }
  if (kind == InputKind::descriptors || kind == InputKind::similarity) {
    if (kind == InputKind::similarity) refuse_every_for_similarity(input);
    const auto header = io::read_npy_header(input.path);
    if (!header.shape.empty()) count = every_kth_count(header.shape[0], input.every);
    // The kind of a .npy comes from its name: a similarity matrix saved under another name would be mapped as
    // descriptors, and quietly give another map. A square symmetric array is almost surely one.
    if (kind == InputKind::descriptors && input.kind == InputKind::automatic && header.shape.size() == 2 &&
        header.shape[0] == header.shape[1] && header.shape[0] >= 2 && header.shape[0] <= kSymmetryCheckRows) {
      const auto m = io::read_npy_matrix<float>(input.path);
      bool symmetric = true;
      for (std::size_t i = 0; i < m.rows && symmetric; ++i) {
        for (std::size_t j = 0; j < i && symmetric; ++j) symmetric = m(i, j) == m(j, i);
      }
      if (symmetric) {
        s.notes.push_back(
            fmt::format("{}: a symmetric {} x {} array, read as descriptors (one row per image) since "
                        "its name has no \"similarity\"; a similarity matrix needs --input-kind "
                        "similarity",
                        input.path.string(), m.rows, m.cols));
      }
    }
  }

  std::vector<Pose2> poses;  // one per frame (after every)
  std::vector<TimedPose> timed;
  std::string timed_subject;
  if (!source.odometry.empty()) {
    const formats::PoseFile file = formats::read_pose_file(source.odometry);
    s.odometry_subject = source.odometry.string();
    if (file.timestamped()) {
      timed = file.timed;
      timed_subject = source.odometry.string();
    } else {
      poses = file.per_frame;
    }
  }
#ifdef SEQTOPO_HAVE_RECORDING
  std::optional<recording::Recording> bag;
  std::string image_topic;
  if (kind == InputKind::bag) {
    bag.emplace(input.path);
    image_topic = bag->image_topic(input.image_topic);
    bag->check_first_image(image_topic);
    count = every_kth_count(bag->message_count(image_topic), input.every);
    if (source.odometry.empty()) {
      if (const auto topic = bag->odometry_topic(source.odometry_topic)) {
        timed = bag->poses(*topic);
        timed_subject = input.path.string() + ":" + *topic;
        s.odometry_subject = timed_subject;
      }
    }
  }
#else
  if (kind == InputKind::bag) {
    throw InputError(input.path.string(),
                     "this seqtopo was built without bag support (scripts/setup.sh installs "
                     "librosbag-dev, libsqlite3-dev, libzstd-dev and liblz4-dev)");
  }
#endif

  std::vector<double> times;  // the frames' times (after every), where the recording has them
#ifdef SEQTOPO_HAVE_RECORDING
  if (bag) times = every_kth(bag->image_times(image_topic), input.every);
#endif
  if (!timed.empty()) {
    if (kind != InputKind::bag) {
      const auto t = frame_times(input, source.times);
      if (!t) {
        throw InputError(source.odometry.string(),
                         "holds timestamped poses, but the images have no times: give --times times.txt, put a "
                         "times.txt in the image folder, or name the images by their time");
      }
      times = *t;
      if (count && times.size() != *count) {
        throw InputError(source.times.empty() ? input.path.string() : source.times.string(),
                         fmt::format("{} image times for {} images", times.size(), *count));
      }
    }
    try {
      const auto matched = timeline::interpolate_poses(timed, times);
      poses = matched.poses;
      s.notes.push_back(fmt::format(
          "odometry from {}: {} poses matched by time to {} images{}", timed_subject, timed.size(), poses.size(),
          matched.held_at_end
              ? fmt::format(" ({} just outside the poses' time range got the end pose)", matched.held_at_end)
              : std::string()));
    } catch (const std::invalid_argument& e) {
      throw InputError(timed_subject, e.what());
    }
  } else if (!poses.empty() && input.every > 1) {
    poses = every_kth(poses, input.every);  // a per-frame file covers every frame of the video, folder or array
  }
  if (times.empty() && kind == InputKind::images) {
    // Only to find session breaks: a folder whose names are not times (or not increasing ones) has none.
    try {
      if (auto t = frame_times(input, source.times)) times = std::move(*t);
    } catch (const InputError&) {
      if (!source.times.empty()) throw;  // a times file the user gave must be right
    }
  }
  if (!poses.empty() && count && poses.size() != *count) {
    throw InputError(s.odometry_subject, fmt::format("has {} poses, the sequence has {} images", poses.size(), *count));
  }

  if (source.every_metres) {
    if (poses.empty()) {
      throw InputError("--every-metres", "needs odometry: give --odometry FILE, or a bag with an odometry topic (" +
                                             input.path.string() + " has none)");
    }
    try {
      s.input.frames = timeline::select_every_metres(poses, *source.every_metres);
    } catch (const std::invalid_argument& e) {
      throw InputError("--every-metres", e.what());
    }
    std::vector<Pose2> kept;
    for (std::size_t k : s.input.frames) kept.push_back(poses[k]);
    s.notes.push_back(
        fmt::format("--every-metres {}: {} of {} frames kept", *source.every_metres, kept.size(), poses.size()));
    poses = std::move(kept);
    count = poses.size();
  }
  s.odometry = std::move(poses);
  s.frames = count;
  // Frames kept one per D metres are uneven in time by design: their intervals say nothing of a cut.
  if (!source.every_metres && count && !times.empty()) {
    if (times.size() != *count && !source.times.empty()) {
      throw InputError(source.times.string(), fmt::format("{} image times for {} images", times.size(), *count));
    }
    if (times.size() == *count) s.times = std::move(times);
  }
  return s;
}

}  // namespace seqtopo::pipeline
