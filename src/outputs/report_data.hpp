#pragma once
// The parts of the interactive reports' data block shared by `map` and `localize` (report/interactive.hpp):
// sequences with thumbnails, the matrix layer, alignments, PR curves, timings, and the page's skeleton.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/evaluation/calibration.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/outputs/report_options.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/plot/pr_curve.hpp"
#include "seqtopo/report/html_report.hpp"

namespace seqtopo::outputs::detail {

// The bytes of a file the run wrote (a staged figure the page embeds); "" when it cannot be read.
std::string read_file(const std::filesystem::path& path);

// metrics.json's and online.json's loop-closure figures.
nlohmann::json loop_closure_metrics_json(const evaluation::LoopClosureMetrics& m);

// {"count", "names", "thumbnails": [data: URI or null per frame], "note"}. Thumbnails exist for image folders and
// videos (descriptor and similarity inputs have no images: the note says so). `wanted` frames come first when
// not every frame can be embedded (more than kMaxThumbnails).
inline constexpr std::size_t kMaxThumbnails = 20000;
// `jpegs` (one per frame, ReportOptions::thumbnails) saves decoding an image folder again.
nlohmann::json sequence_json(const pipeline::SequenceInput& input, std::size_t frames,
                             const std::vector<std::size_t>& wanted, const std::string& noun,
                             const std::vector<std::string>* jpegs = nullptr);

// Static figures larger than this are left out of the page (they are files beside it) [bytes].
inline constexpr std::size_t kMaxInlinedFigure = std::size_t{3} << 20U;

// {"image": PNG (JPEG above 1024 pixels a side) data URI of the grey levels, "rows", "cols" (the index extents),
// "range": [lo, hi], labels}.
nlohmann::json matrix_json(const DenseMatrix<float>& cells, std::size_t rows, std::size_t cols,
                           const std::string& row_label, const std::string& col_label, const std::string& value_label);

// One alignment: {"id", "direction", "kept", "score", "a": [begin, end), "b", "pairs", "path": [[i, j], ...]}
// with the path thinned to at most 400 points.
nlohmann::json alignment_json(const align::LocalAlignment& a, std::size_t id, bool kept);

// {"curves": [{"label", "primary", "colour", "points": [[recall, precision, threshold]]}]}.
struct CurvePoints {
  std::string label;
  std::string colour;
  std::vector<std::array<double, 3>> points;  // recall, precision, threshold
};
// metrics.json's reliability diagram: {"ece", "<count_name>", "bins": [{"lower", "upper", "count",
// "mean_confidence", "accuracy"}]}.
nlohmann::json calibration_json(const evaluation::Calibration& c, const char* count_name);

// The report's reliability diagram: an inline SVG of each bin's share right against its mean confidence (the
// diagonal is perfect calibration), the expected calibration error, and the bins as a table. `what` names the
// detections ("loop-closure pairs", "query frames").
void reliability_section(report::HtmlReport& html, const evaluation::Calibration& c, const std::string& what);

nlohmann::json pr_json(const std::vector<CurvePoints>& curves);

// {"rows": [[stage, seconds]], "wall"}: `rows`, then the report's own time since `report_start`, then the rest
// of the wall time (options.seconds_before) not in any row. Also returns the rows for the table.
nlohmann::json timings_json(std::vector<std::pair<std::string, double>>& rows, const ReportOptions& options,
                            std::chrono::steady_clock::time_point report_start);

// The interactive page: the views' skeletons are added by the caller; this inlines the data, D3 and the script,
// or, when D3 is missing, says so in the page and returns the warning.
ReportResult finish_interactive(report::HtmlReport& html, const nlohmann::json& data);

// Under the report's title: seqtopo's version and the command line that made the run (when known).
void provenance(report::HtmlReport& html, const ReportOptions& options);

// The skeleton of the matrix view and its pair viewer.
std::string matrix_view_markup(const std::string& help);

}  // namespace seqtopo::outputs::detail
