#include "progress.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "seqtopo/pipeline/memory_estimate.hpp"

namespace seqtopo::cli {
namespace {

constexpr auto kBarInterval = std::chrono::milliseconds(100);  // redraws of the bar
constexpr auto kLineInterval = std::chrono::seconds(2);        // longest silence in the lines style

int terminal_columns() {
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 20) return size.ws_col;
  if (const char* columns = std::getenv("COLUMNS")) {
    const int c = std::atoi(columns);
    if (c >= 20) return c;
  }
  return 80;
}

std::string duration_text(double seconds) {
  if (seconds < 60) return fmt::format("{:.0f} s", std::ceil(seconds));
  const auto s = static_cast<long>(std::lround(seconds));
  if (s < 3600) return fmt::format("{}:{:02d} min", s / 60, s % 60);
  return fmt::format("{}:{:02d} h", s / 3600, (s / 60) % 60);
}

std::string rate_text(double per_second) {
  if (per_second >= 1e6) return fmt::format("{:.1f}M/s", per_second / 1e6);
  if (per_second >= 1e4) return fmt::format("{:.0f}k/s", per_second / 1e3);
  if (per_second >= 10) return fmt::format("{:.0f}/s", per_second);
  return fmt::format("{:.2g}/s", per_second);
}

// The run's clock starts at the launcher's main (src/launcher/main.cpp hands its CLOCK_BOOTTIME over in
// SEQTOPO_STARTED_NS), else when this program is loaded: never at the process's start, which is the start of
// whatever exec'd it (scripts/run.sh builds seqtopo, then execs it: that build is not seqtopo's start-up).
double boottime_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_BOOTTIME, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double start_seconds() {
  const double now = boottime_seconds();
  double start = now;
  if (const char* handed = std::getenv("SEQTOPO_STARTED_NS")) {
    char* end = nullptr;
    const unsigned long long ns = std::strtoull(handed, &end, 10);
    const double at = 1e-9 * static_cast<double>(ns);
    if (end != handed && *end == '\0' && at <= now) start = at;
    ::unsetenv("SEQTOPO_STARTED_NS");  // not inherited by the programs seqtopo starts
  }
  return start;
}

const double kStartSeconds = start_seconds();  // at load, before main

// How long this run has taken [s], from its start above.
double process_age() { return std::max(0.0, boottime_seconds() - kStartSeconds); }

}  // namespace

ProgressStyle progress_style() {
  if (const char* forced = std::getenv("SEQTOPO_PROGRESS")) {
    const std::string_view v(forced);
    if (v == "bar") return ProgressStyle::bar;
    if (v == "lines") return ProgressStyle::lines;
    if (v == "none") return ProgressStyle::none;
  }
  return isatty(STDERR_FILENO) ? ProgressStyle::bar : ProgressStyle::lines;
}

Progress::Progress(std::string command, ProgressStyle style, std::ostream* out)
    : command_(std::move(command)), style_(style), out_(out ? *out : std::cerr), age_at_creation_(process_age()) {
  last_output_ = created_;
  if (style_ != ProgressStyle::none) ticker_ = std::thread([this] { tick(); });
}

Progress::~Progress() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
    clear_bar_locked();
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
}

void Progress::plan(std::vector<std::string> names) {
  const std::lock_guard lock(mutex_);
  names_ = std::move(names);
  stage_ = 0;
}

void Progress::plan_more(const std::vector<std::string>& names) {
  const std::lock_guard lock(mutex_);
  names_.insert(names_.end(), names.begin(), names.end());
}

void Progress::begin(std::string_view name) {
  const std::lock_guard lock(mutex_);
  if (stage_ >= names_.size() || names_[stage_] != name) {
    throw std::logic_error(fmt::format("progress: stage '{}' is not the next one planned", name));
  }
  ++stage_;
  running_ = true;
  stage_start_ = unit_start_ = Clock::now();
  done_ = total_ = 0;
  unit_.clear();
  if (style_ == ProgressStyle::lines) print_locked(stage_label_locked());
  if (style_ == ProgressStyle::bar) draw_bar_locked();
}

void Progress::advance(std::size_t done, std::size_t total, std::string_view unit) {
  const std::lock_guard lock(mutex_);
  if (!running_) return;
  const bool first = unit_.empty() && done_ == 0 && total_ == 0;
  done_ = done;
  total_ = total;
  if (unit_ != unit) {  // a step of its own (a stage may count several in turn): its rate from now
    unit_ = unit;
    unit_start_ = Clock::now();
  }
  if (first && style_ == ProgressStyle::bar) draw_bar_locked();
}

double Progress::end() {
  const std::lock_guard lock(mutex_);
  if (!running_) return 0;
  running_ = false;
  const double seconds = std::chrono::duration<double>(Clock::now() - stage_start_).count();
  if (style_ != ProgressStyle::none) {
    // The process's peak so far: the stage whose line first shows the run's peak is the one that reached it.
    const std::size_t peak = pipeline::peak_resident_bytes();
    print_locked(peak == 0 ? fmt::format("{} done in {:.2f} s", stage_label_locked(), seconds)
                           : fmt::format("{} done in {:.2f} s (peak memory {:.0f} MB)", stage_label_locked(), seconds,
                                         static_cast<double>(peak) / 1e6));
  }
  return seconds;
}

void Progress::line(std::string_view text) {
  const std::lock_guard lock(mutex_);
  print_locked(std::string(text));  // also with the none style: these are results and warnings, not progress
}

void Progress::on_event(const pipeline::StageEvent& event) {
  using Kind = pipeline::StageEvent::Kind;
  switch (event.kind) {
    case Kind::plan: {
      const std::lock_guard lock(mutex_);
      // The job's stages first, then whatever the command planned after them (the job tells its own and the
      // later ones in one list when it knows them: event.names has all of them).
      std::vector<std::string> names = event.names ? *event.names : std::vector<std::string>{};
      if (names.size() < event.stages) names.resize(event.stages, "stage");
      names_ = std::move(names);
      stage_ = 0;
      return;
    }
    case Kind::begin:
      begin(event.name);
      return;
    case Kind::advance:
      advance(event.done, event.total, event.unit);
      return;
    case Kind::end:
      end();
      return;
  }
}

pipeline::StageObserver Progress::observer() {
  return [this](const pipeline::StageEvent& event) { on_event(event); };
}

double Progress::elapsed() const {
  return age_at_creation_ + std::chrono::duration<double>(Clock::now() - created_).count();
}

void Progress::pause_bar(bool paused) {
  const std::lock_guard lock(mutex_);
  paused_ = paused;
  if (paused) clear_bar_locked();
}

void Progress::tick() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, kBarInterval);
    if (stop_ || !running_) continue;
    if (style_ == ProgressStyle::bar) {
      draw_bar_locked();
    } else if (Clock::now() - last_output_ >= kLineInterval) {
      print_locked(stage_label_locked() + ": " + status_locked());
    }
  }
}

std::string Progress::stage_label_locked() const {
  const std::string name = stage_ >= 1 && stage_ <= names_.size() ? names_[stage_ - 1] : std::string("working");
  return fmt::format("[{}/{}] {}", stage_, names_.size(), name);
}

Progress::Counts Progress::counts_locked() const {
  Counts c;
  c.fraction = std::min(1.0, static_cast<double>(done_) / static_cast<double>(total_));
  const double counting = std::chrono::duration<double>(Clock::now() - unit_start_).count();
  c.rate = counting > 0 ? static_cast<double>(done_) / counting : 0;
  c.eta = c.rate > 0 ? static_cast<double>(total_ - std::min(done_, total_)) / c.rate : 0;
  return c;
}

// "45% (1620/3600 images described), 310/s, ETA 6 s", or "running, 4 s" without counts.
std::string Progress::status_locked() const {
  const double seconds = std::chrono::duration<double>(Clock::now() - stage_start_).count();
  if (total_ == 0 || done_ == 0) {
    if (done_ > 0) return fmt::format("{} {}, {:.0f} s", done_, unit_, seconds);
    return fmt::format("running, {:.0f} s", seconds);
  }
  const Counts c = counts_locked();
  return fmt::format("{:.0f}% ({}/{} {}), {}, ETA {}", 100 * c.fraction, done_, total_, unit_, rate_text(c.rate),
                     duration_text(c.eta));
}

void Progress::clear_bar_locked() {
  if (!bar_shown_) return;
  out_ << "\r\x1b[2K" << std::flush;
  bar_shown_ = false;
}

void Progress::draw_bar_locked() {
  if (paused_ || !running_) return;
  const int columns = terminal_columns();
  const double seconds = std::chrono::duration<double>(Clock::now() - stage_start_).count();
  std::string text;
  if (total_ > 0 && done_ > 0) {
    const Counts c = counts_locked();
    text = fit_bar({command_, stage_label_locked(), c.fraction, done_, total_, unit_, rate_text(c.rate),
                    duration_text(c.eta), seconds},
                   columns);
  } else {
    // no counts: a spinner shows that the stage is alive
    static constexpr char kSpin[] = {'|', '/', '-', '\\'};
    const auto ticks = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - stage_start_).count() /
                       kBarInterval.count();
    text = command_ + ": " + stage_label_locked() + " " + std::string(1, kSpin[ticks % 4]) + " " + status_locked();
    if (static_cast<int>(text.size()) >= columns) text.resize(static_cast<std::size_t>(std::max(1, columns - 1)));
  }
  out_ << "\r\x1b[2K" << text << std::flush;
  bar_shown_ = true;
  last_output_ = Clock::now();
}

std::string fit_bar(const BarParts& p, int columns) {
  const auto bar = [&](int width) {
    const int filled = static_cast<int>(p.fraction * width);
    std::string b(static_cast<std::size_t>(width), ' ');
    for (int k = 0; k < filled; ++k) b[static_cast<std::size_t>(k)] = '=';
    if (filled < width) b[static_cast<std::size_t>(filled)] = '>';
    return "[" + b + "] ";
  };
  const std::string head = p.command + ": " + p.label + " ";
  const std::string percent = fmt::format("{:.0f}%", 100 * p.fraction), eta = "ETA " + p.eta;
  const std::string counts = fmt::format("{}/{}", p.done, p.total);
  // From the fullest to the barest; the first that fits is drawn. The percentage and the ETA stay to the last.
  const std::string candidates[] = {
      head + bar(24) + fmt::format("{:>4}  {} {}  {}  {}  ({:.0f} s)", percent, counts, p.unit, p.rate, eta, p.seconds),
      head + bar(24) + fmt::format("{:>4}  {}  {}  {}", percent, counts, p.rate, eta),
      head + bar(16) + fmt::format("{:>4}  {}  {}", percent, p.rate, eta),
      head + bar(10) + fmt::format("{:>4}  {}", percent, eta),
      head + percent + "  " + eta,
      p.command + ": " + percent + "  " + eta,
  };
  for (const auto& c : candidates) {
    if (static_cast<int>(c.size()) < columns) return c;
  }
  std::string last = candidates[std::size(candidates) - 1];
  last.resize(static_cast<std::size_t>(std::max(1, columns - 1)));
  return last;
}

void Progress::print_locked(const std::string& text) {
  clear_bar_locked();
  out_ << command_ << ": " << text << "\n" << std::flush;
  last_output_ = Clock::now();
  if (style_ == ProgressStyle::bar && running_) draw_bar_locked();
}

}  // namespace seqtopo::cli
