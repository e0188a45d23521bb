#pragma once
// Structured progress of a long job, for whoever shows it (the command line draws a bar on a terminal and
// plain lines elsewhere, src/cli/progress.hpp); the library never prints.
//
// A job announces its numbered stages once (`plan`), then sends, per stage, one `begin`, any number of
// `advance` (units of work done of a total, when the stage can count them) and one `end` with the stage's
// wall time. Stage numbers are consistent: stage k of `stages`, every stage that runs announced in the plan.
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::pipeline {

struct StageEvent {
  enum class Kind { plan, begin, advance, end };
  Kind kind = Kind::begin;
  std::size_t stage = 0;                            // 1-based number of the stage (0 for plan)
  std::size_t stages = 0;                           // how many stages the job runs
  std::string_view name = {};                       // e.g. "similarity"; plan: empty
  std::size_t done = 0;                             // advance: units of work done ...
  std::size_t total = 0;                            // ... of this many (0 = not known)
  std::string_view unit = {};                       // advance: what a unit is ("images", "rows of the matrix", ...)
  double seconds = 0;                               // end: the stage's wall time [s]
  const std::vector<std::string>* names = nullptr;  // plan: every stage's name, in order
};

// Called from one thread at a time (the job serialises its calls); may be empty.
using StageObserver = std::function<void(const StageEvent&)>;

}  // namespace seqtopo::pipeline
