#pragma once
// One session of a map: a sequence with its odometry, matched by time when the odometry is timestamped, and
// thinned to one frame per D metres when asked (docs/recordings.md). Several sessions make one map
// (seqtopo map S1 S2 ...): their frames one after the other, no transition between one's end and the next
// one's start.
//
//   pipeline::SessionSource run{{"run.bag"}};                 // images and odometry from the bag's topics
//   run.every_metres = 0.5;
//   pipeline::PreparedSession s = pipeline::prepare_session(run);   // s.input.frames: the kept frames
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "seqtopo/core/pose2.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"

namespace seqtopo::pipeline {

// Default member initializers: `SessionSource{{"run.bag"}}` alone stays free of -Wmissing-field-initializers.
struct SessionSource {
  SequenceInput input;
  // Odometry or poses: index CSV, timestamped CSV, TUM or KITTI (formats/pose_files.hpp), or empty. A bag
  // without a file uses its odometry topic (below).
  std::filesystem::path odometry = {};
  // Image times for a timestamped pose file and an image folder or video: a times.txt (one time per frame
  // [s]); empty = `times.txt` in the image folder when there is one, else the file names when every one is a
  // number (seconds, or nanoseconds when above 1e15, as EuRoC names them). Bags carry their own times.
  std::filesystem::path times = {};
  // Bags: the odometry topic; empty = the bag's only nav_msgs/Odometry or PoseStamped topic, if any;
  // "none" = do not use the bag's odometry.
  std::string odometry_topic = {};
  // Keep one frame per this many metres of odometry travelled (needs odometry) [m].
  std::optional<double> every_metres = {};
};

struct PreparedSession {
  SequenceInput input;                // with `frames` set when frames were selected
  std::vector<Pose2> odometry;        // one per kept frame, or empty
  std::string odometry_subject;       // where the odometry came from (file, or bag:topic), for errors and reports
  std::optional<std::size_t> frames;  // number of kept frames, when known without decoding
  // The kept frames' times [s] (times.txt, names that are times, a bag's stamps), or empty: a long gap in them
  // may be a session break (timeline/session_breaks.hpp). None with --every-metres (uneven by design).
  std::vector<double> times;
  std::vector<std::string> notes;  // what was done ("odometry from /odom, 812 poses matched to 2520 images")
};

// Reads what a session needs before any image is described: the frame count, the odometry and its match to
// the frames, the frames kept. Throws InputError naming the file (and line) or the option on any problem:
// odometry with a different number of poses than frames, time ranges that do not overlap, --every-metres
// without odometry.
PreparedSession prepare_session(const SessionSource& source);

// The time of each frame of an image folder or video [s] (before `every`), from `times` or as described for
// SessionSource::times; nullopt when there is none. Throws InputError on a bad times.txt.
std::optional<std::vector<double>> frame_times(const SequenceInput& input, const std::filesystem::path& times);

}  // namespace seqtopo::pipeline
