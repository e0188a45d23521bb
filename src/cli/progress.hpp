#pragma once
// Progress of a long command on stderr: numbered stages, each one's time printed as it ends, and in between
//   on a terminal: one bar redrawn in place ten times a second, with the units done, the rate and the ETA
//     seqtopo map: [1/6] similarity [=========>          ]  45%  1620/3600 images described  310/s  ETA 6 s
//   elsewhere (a pipe, a log file): plain lines, one when a stage starts, one at least every 2 s while it
//   runs (nothing is silent for longer), one when it ends
//     seqtopo map: [1/6] similarity: 45% (1620/3600 images described), 310/s, ETA 6 s
//     seqtopo map: [1/6] similarity done in 11.62 s (peak memory 378 MB)
//   (the peak: the process's largest resident memory so far)
// SEQTOPO_PROGRESS=bar|lines|none overrides the choice (tests, or a terminal that wants plain lines); none keeps
// the detail lines (sizes, results, warnings) and drops the stages.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <ostream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "seqtopo/pipeline/progress.hpp"

namespace seqtopo::cli {

enum class ProgressStyle { bar, lines, none };

// The bar of a stage that counts its work, fitted to `columns` (the terminal's width, 80 on most): the fullest
// form that fits (bar, percentage, counts and unit, rate, ETA, seconds so far), then shorter ones that drop the
// counts, the rate and the bar's width, so that the percentage and the ETA are always shown.
struct BarParts {
  std::string command, label;
  double fraction = 0;
  std::size_t done = 0, total = 0;
  std::string unit, rate, eta;
  double seconds = 0;
};
std::string fit_bar(const BarParts& parts, int columns);

// SEQTOPO_PROGRESS when set, else bar when stderr is a terminal, else lines.
ProgressStyle progress_style();

class Progress {
 public:
  // `command`: the prefix of every line ("seqtopo map"). Starts a ticker thread (bar and lines styles).
  explicit Progress(std::string command, ProgressStyle style = progress_style(), std::ostream* out = nullptr);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // The stages of the whole command, numbered 1..n in this order.
  void plan(std::vector<std::string> names);
  // Adds stages after the planned ones (a command's own stages after a job's).
  void plan_more(const std::vector<std::string>& names);
  // Starts the next planned stage; `name` must be its name (a mismatch is a programming error and throws).
  void begin(std::string_view name);
  // Units done of total (total 0 = not known); may be called from any thread.
  void advance(std::size_t done, std::size_t total, std::string_view unit);
  // Ends the current stage, prints its time and returns it [s].
  double end();
  // A detail line (sizes, notes); the bar is redrawn under it.
  void line(std::string_view text);

  // Events of a library job (pipeline/progress.hpp): its plan (the job's stages and the later ones it was
  // told, MapObserver::later_stages) replaces the plan; begin/advance/end as above.
  void on_event(const pipeline::StageEvent& event);
  pipeline::StageObserver observer();

  // Seconds since the run started: the launcher's main (its start-up included), else this program's loading.
  double elapsed() const;
  ProgressStyle style() const { return style_; }
  // Stops drawing the bar until pause_bar(false) (while another output shares the terminal); lines still print.
  void pause_bar(bool paused);

 private:
  using Clock = std::chrono::steady_clock;
  void tick();
  void clear_bar_locked();
  void draw_bar_locked();
  void print_locked(const std::string& text);
  // The fraction done, the rate of the current unit [a second] and the time left [s]; with counts (total_ > 0).
  struct Counts {
    double fraction = 0, rate = 0, eta = 0;
  };
  Counts counts_locked() const;
  std::string status_locked() const;
  std::string stage_label_locked() const;

  std::string command_;
  ProgressStyle style_;
  std::ostream& out_;
  Clock::time_point created_ = Clock::now();
  double age_at_creation_ = 0;  // [s] how long the process had run when this was made

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread ticker_;

  std::vector<std::string> names_;
  std::size_t stage_ = 0;  // 1-based, 0 before the first stage
  bool running_ = false;   // a stage has begun and not ended
  bool paused_ = false;
  bool bar_shown_ = false;
  Clock::time_point stage_start_, last_output_;
  Clock::time_point unit_start_;  // when the stage began counting its current unit: the rate and ETA are of it
  std::size_t done_ = 0, total_ = 0;
  std::string unit_;
};

}  // namespace seqtopo::cli
