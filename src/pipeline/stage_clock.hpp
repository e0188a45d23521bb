#pragma once
// The map pipeline's numbered stages (map_pipeline.cpp): the plan, each stage's begin and end, its time in
// MapRun::timings and the observer's events (pipeline/progress.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/pipeline/map_pipeline.hpp"

namespace seqtopo::pipeline::detail {

// The run's numbered stages: announced once, then begun and ended in order; each stage's time goes to
// run.timings (so that they add up to the run's wall time) and to the observer.
class StageClock {
 public:
  StageClock(const MapObserver& observer, MapRun& run, std::vector<std::string> names)
      : observer_(observer), run_(run), names_(std::move(names)) {
    names_.insert(names_.end(), observer.later_stages.begin(), observer.later_stages.end());
    send({.kind = StageEvent::Kind::plan, .stages = names_.size(), .names = &names_});
  }
  // The next stage of the plan. `detail` is added to its text line when there is no structured observer.
  void begin(const std::string& detail = {}) {
    if (stage_ >= names_.size()) throw std::logic_error("map pipeline: more stages than planned");
    ++stage_;
    start_ = std::chrono::steady_clock::now();
    if (observer_.stage) {
      send({.kind = StageEvent::Kind::begin, .stage = stage_, .stages = names_.size(), .name = names_[stage_ - 1]});
    } else {
      if (observer_.progress)
        observer_.progress(fmt::format("[{}/{}] {}{}", stage_, names_.size(), names_[stage_ - 1], detail));
    }
  }
  void advance(std::size_t done, std::size_t total, std::string_view unit) {
    send({.kind = StageEvent::Kind::advance,
          .stage = stage_,
          .stages = names_.size(),
          .name = names_[stage_ - 1],
          .done = done,
          .total = total,
          .unit = unit});
  }
  // Ends the stage; its time is recorded as `parts` (name, seconds) with the rest of the stage's time given to
  // the last part (default: the stage's own name). Returns the stage's seconds.
  double end(std::vector<std::pair<std::string, double>> parts = {}) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (parts.empty()) parts.emplace_back(names_[stage_ - 1], 0.0);
    double others = 0;
    for (std::size_t k = 0; k + 1 < parts.size(); ++k) others += parts[k].second;
    parts.back().second = std::max(0.0, seconds - others);
    run_.timings.insert(run_.timings.end(), parts.begin(), parts.end());
    send({.kind = StageEvent::Kind::end,
          .stage = stage_,
          .stages = names_.size(),
          .name = names_[stage_ - 1],
          .seconds = seconds});
    return seconds;
  }
  // For SimilarityConfig::progress: the similarity's own counts (images described, matrix cells).
  std::function<void(std::string_view, std::size_t, std::size_t)> similarity_progress() {
    if (!observer_.stage) return {};
    return [this](std::string_view what, std::size_t done, std::size_t total) {
      advance(done, total, what == "matrix" ? "cells of the matrix" : "images described");
    };
  }
  // For MapConfig::progress: each step's own counts (similarities enhanced, descriptors mapped alone, statistics'
  // fits, cells aligned; the cells told from the alignment passes' threads, passed on one at a time).
  std::function<void(std::string_view, std::size_t, std::size_t)> map_progress() {
    if (!observer_.stage) return {};
    return [this](std::string_view what, std::size_t done, std::size_t total) {
      const std::lock_guard<std::mutex> lock(advance_mutex_);
      advance(done, total, what);
    };
  }

 private:
  void send(const StageEvent& event) const {
    if (observer_.stage) observer_.stage(event);
  }
  const MapObserver& observer_;
  MapRun& run_;
  std::vector<std::string> names_;
  std::size_t stage_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::mutex advance_mutex_;
};

// The stages a run goes through, in order (the plan's names).
std::vector<std::string> stage_names(bool streaming, bool from_memory, bool odometry, bool truth, bool same_place) {
  std::vector<std::string> names;
  if (streaming) {
    names = {"descriptors", "alignments, pruning, labels, topology (streamed scores)", "similarity overview"};
  } else {
    if (!from_memory) names.emplace_back("similarity");
    names.emplace_back("alignments, pruning, labels, topology");
  }
  if (odometry) names.emplace_back("metric picture");
  if (truth) names.emplace_back("accuracy");
  if (same_place && !streaming) names.emplace_back("SeqSLAM-style baseline");
  return names;
}

}  // namespace seqtopo::pipeline::detail
