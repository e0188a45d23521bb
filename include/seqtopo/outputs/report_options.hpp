#pragma once
// What a report is told about the run around it, and what it says back.
#include <cstddef>
#include <optional>
#include <string>

namespace seqtopo::outputs {

struct ReportOptions {
  // Seconds the command had run when the report started (the command line's clock): the report's timings then
  // add up to the wall time, the gap between the stages shown as its own row. Without it they add up to the
  // stages' sum.
  std::optional<double> seconds_before;
  // The command that made the run, shown under the report's title with seqtopo's version (empty: the version
  // alone, as for a run from the Python module).
  std::string command_line;
};

// The side of the report's image thumbnails [pixels]: larger sequences get smaller ones, so that the page
// stays a few megabytes.
inline int report_thumbnail_side(std::size_t frames) {
  if (frames <= 600) return 200;
  if (frames <= 4000) return 96;
  return 64;
}

struct ReportResult {
  bool interactive = true;  // false: D3 was not found and the report is static
  std::string warning;      // one line for the user when something is missing, else empty
};

}  // namespace seqtopo::outputs
