#pragma once
// What a report is told about the run around it, and what it says back.
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::outputs {

struct ReportOptions {
  // Seconds the command had run when the report started (the command line's clock): the report's timings then
  // add up to the wall time, the gap between the stages shown as its own row. Without it they add up to the
  // stages' sum.
  std::optional<double> seconds_before;
  // The command that made the run, shown under the report's title with seqtopo's version (empty: the version
  // alone, as for a run from the Python module).
  std::string command_line;
  // JPEG thumbnails of the images, one per image (ThumbnailCollector), made while the run read them; empty: the
  // report decodes the images again.
  const std::vector<std::string>* thumbnails = nullptr;
  // localize: the map's (the columns'); `thumbnails` are the query's.
  const std::vector<std::string>* column_thumbnails = nullptr;
};

// The side of the report's image thumbnails [pixels]: larger sequences get smaller ones, so that the page
// stays a few megabytes.
inline int report_thumbnail_side(std::size_t frames) {
  if (frames <= 600) return 200;
  if (frames <= 4000) return 96;
  return 64;
}

// The report's thumbnails made as a run reads its images (pipeline::MapObserver::on_image, called from the
// describing threads), so that the report need not decode them again: each image shrunk to `side` pixels, JPEG at
// quality 75, at its index.
class ThumbnailCollector {
 public:
  // The images of sessions of these lengths (one sequence: one session), counted one session after the other: each
  // session's at the side the report gives a sequence of its length (report_thumbnail_side).
  explicit ThumbnailCollector(const std::vector<std::size_t>& session_frames);
  void add(std::size_t index, const RgbImage& image);
  const std::vector<std::string>& jpegs() const { return jpegs_; }

 private:
  std::vector<std::pair<std::size_t, int>> sides_;  // (end of a session's indices, its side), ascending
  std::mutex mutex_;
  std::vector<std::string> jpegs_;
};

struct ReportResult {
  bool interactive = true;  // false: D3 was not found and the report is static
  std::string warning;      // one line for the user when something is missing, else empty
};

}  // namespace seqtopo::outputs
