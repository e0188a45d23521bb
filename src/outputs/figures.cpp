#include "figures.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace seqtopo::outputs {

DrawnMatrix::DrawnMatrix(const pipeline::MapRun& run) {
  if (run.streamed()) {
    cells_ = &run.overview.cells;
    block_ = run.overview.block;
  } else if (std::max(run.result.scores.rows, run.result.scores.cols) > kMaxDrawnSide) {
    own_ = plot::matrix_overview(run.result.scores, kMaxDrawnSide);
    cells_ = &own_.cells;
    block_ = own_.block;
  } else {
    cells_ = &run.result.scores;
  }
}

plot::MatrixFigureConfig map_similarity_figure(const pipeline::MapRun& run, std::size_t block) {
  plot::MatrixFigureConfig c;
  const std::size_t n = run.result.map.labels.size();
  c.rows = c.cols = n;
  c.row_label = "image i";
  c.column_label = "image j";
  const bool contrast = run.streamed() || run.map_config.score.contrast_window > 0;
  c.title = contrast ? fmt::format("Contrast-enhanced similarity of {} images", n)
                     : fmt::format("Similarity S = 1 - kappa D of {} images", n);
  c.value_label = contrast ? "score [sd]" : "similarity S";
  if (block > 1) {
    c.block = block;
    c.title += fmt::format(" (block maxima, {} x {} per pixel)", block, block);
  }
  c.legend = {{"alignment, pruned", {40, 110, 255}, plot::LegendEntry::Mark::line},
              {"retained loop closures", {255, 30, 30}, plot::LegendEntry::Mark::line}};
  if (run.errors) {
    c.legend.push_back({fmt::format("false positive ({})", run.errors->false_positives.size()), kFalsePositiveColour,
                        plot::LegendEntry::Mark::hollow_square});
    c.legend.push_back({fmt::format("missed revisit ({})", run.errors->missed.size()), kMissedColour,
                        plot::LegendEntry::Mark::hollow_square});
  }
  return c;
}

plot::MatrixFigureConfig localize_similarity_figure(const pipeline::LocalizeRun& run) {
  plot::MatrixFigureConfig c;
  c.rows = run.similarity.rows;
  c.cols = run.similarity.cols;
  c.row_label = "query frame";
  c.column_label = "map frame";
  c.value_label = "similarity";
  c.title = fmt::format("Query ({}) x map ({}) similarity", run.queries, run.maps);
  c.image.max_size = 1024;  // the report inlines it; block means keep the alignment lines visible
  if (!run.online) {
    c.legend = {{"forward alignment", {230, 30, 30}, plot::LegendEntry::Mark::line},
                {"reverse alignment", {30, 200, 60}, plot::LegendEntry::Mark::line}};
  }
  return c;
}

}  // namespace seqtopo::outputs
