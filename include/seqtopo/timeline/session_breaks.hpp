#pragma once
// Session breaks inside one recording: where consecutive frames are not neighbours (two passes concatenated,
// the camera paused while the robot was carried elsewhere), the map starts a new session there (no topological
// edge across it), as it does between inputs given as sessions.
//
// The evidence is the frames' times: an interval far longer than the recording's own. A robot that only paused
// (or a camera that records on motion) is told apart by its frames: after the pause the next frame still looks
// like a neighbour, as consecutive frames of the same recording do. Appearance alone does not decide: at the
// frame rates of real recordings consecutive frames of a continuous walk can be as unlike as frames across a cut
// (docs/limitations.md has the measurement), so a break is never declared from appearance alone.
//
//   auto gaps = timeline::time_gaps(times);                         // candidate breaks, by time
//   for (auto& g : gaps)
//     if (!timeline::looks_like_neighbours(similarity, g.frame - 1, g.frame, 0, n)) ... a break before g.frame
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "seqtopo/core/running_median.hpp"

namespace seqtopo::timeline {

struct SessionBreakConfig {
  // A gap: an interval at least this many times the recording's median interval, and at least min_gap long.
  double gap_factor = 10.0;
  double min_gap = 1.0;  // [s]
  // The frames across a gap look like neighbours when their rank (neighbour_rank) is at least this quantile of
  // the ranks of the recording's own consecutive frames, and at least min_neighbour_rank: two unrelated frames
  // rank about uniformly, so a cut is taken for a pause one time in ten at most, even where consecutive frames
  // are hardly alike (low frame rates; there a pause is more often taken for a cut, which costs the map one
  // edge, where a missed cut would add a false one).
  double neighbour_quantile = 0.25;
  double min_neighbour_rank = 0.9;
  // Ranks are measured against at most this many frames, spread evenly (a sample keeps them cheap at 10^6
  // frames), over at most this many of the recording's steps.
  std::size_t rank_columns = 1024;
  std::size_t rank_steps = 64;
};

struct TimeGap {
  std::size_t frame = 0;       // the first frame after the gap
  double gap = 0;              // times[frame] - times[frame - 1] [s]
  double median_interval = 0;  // the recording's median interval [s]
};

// The gaps of `times` (non-decreasing, one per frame) by the rule above, in order; none with fewer than three
// frames or a median interval of zero. Throws std::invalid_argument when a time is not finite or times decrease.
std::vector<TimeGap> time_gaps(std::span<const double> times, const SessionBreakConfig& config = {});

// How alike frames a and b are, as the share of the other frames that each is less alike to than to the
// other (the lower of a's and b's shares): 1 for mutual nearest neighbours, about one half for two unrelated
// frames. The other frames are those of [begin, end) (a sample of config.rank_columns of them, evenly spread),
// a and b left out.
using Similarity = std::function<double(std::size_t, std::size_t)>;
double neighbour_rank(const Similarity& similarity, std::size_t a, std::size_t b, std::size_t begin, std::size_t end,
                      const SessionBreakConfig& config = {});

// Whether a and b look like neighbours: their neighbour_rank is at least config.min_neighbour_rank and
// config.neighbour_quantile of the ranks of the consecutive frames of [begin, end) (config.rank_steps of them, evenly
// spread, leaving out `a`'s step and the frames `skip` says carry no evidence).
bool looks_like_neighbours(const Similarity& similarity, std::size_t a, std::size_t b, std::size_t begin,
                           std::size_t end, const std::function<bool(std::size_t)>& skip = {},
                           const SessionBreakConfig& config = {});

// The same rule as the frames arrive (seqtopo map --online): the median interval and the recording's own step
// ranks are those of the frames so far in the session, and the other frames a rank counts are the earlier ones.
//
//   OnlineBreakFinder finder;
//   finder.start_session();                          // before each input's first frame
//   auto gap = finder.add(time, rows);               // rows: the frame's similarity to every earlier frame
//   if (gap && gap->session_break) ...
class OnlineBreakFinder {
 public:
  explicit OnlineBreakFinder(const SessionBreakConfig& config = {}) : config_(config) {}
  // The next frame begins a new session (an input's first frame): no step into it.
  void start_session();
  struct Gap {
    TimeGap gap;
    bool session_break = false;  // false: the frames either side look like neighbours (a pause)
  };
  // The next frame: its time [s] (nullopt: the session has no times) and its similarity to every earlier frame of
  // the run, one row per descriptor (row[j] for frames j before it, higher = more alike). Returns the gap before
  // it, if there is one, and whether it is a session break. Throws std::invalid_argument on a time that is not
  // finite or goes back, or rows of the wrong length.
  std::optional<Gap> add(std::optional<double> time, const std::vector<std::vector<float>>& rows);

 private:
  SessionBreakConfig config_;
  std::size_t frames_ = 0, begin_ = 0;  // frames of the run so far; the session's first
  std::optional<double> last_time_;
  RunningMedian intervals_;                      // the session's intervals so far
  std::vector<std::vector<float>> previous_;     // the previous frame's rows
  std::vector<std::vector<double>> step_ranks_;  // per descriptor, the session's steps so far
};

}  // namespace seqtopo::timeline
