#pragma once
// Wall time of a step, for the timings a run reports (never for a decision: results do not depend on time).
#include <chrono>

namespace seqtopo {

using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

}  // namespace seqtopo
