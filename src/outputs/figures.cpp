#include "figures.hpp"

#include <fmt/format.h>

namespace seqtopo::outputs {

plot::MatrixFigureConfig map_similarity_figure(const pipeline::MapRun& run) {
  plot::MatrixFigureConfig c;
  const std::size_t n = run.result.map.labels.size();
  c.rows = c.cols = n;
  c.row_label = "image i";
  c.column_label = "image j";
  if (run.streaming && run.overview.block > 1) {
    c.block = run.overview.block;
    c.title = fmt::format("Contrast-enhanced similarity of {} images (block maxima, {} x {} per pixel)", n,
                          run.overview.block, run.overview.block);
    c.value_label = "score [sd]";
  } else if (run.streaming || run.map_config.contrast_window > 0) {  // a streamed overview of block 1: the scores
    c.title = fmt::format("Contrast-enhanced similarity of {} images", n);
    c.value_label = "score [sd]";
  } else {
    c.title = fmt::format("Similarity S = 1 - kappa D of {} images", n);
    c.value_label = "similarity S";
  }
  c.legend = {{"alignment, pruned", {40, 110, 255}, plot::LegendEntry::Mark::line},
              {"retained loop closures", {255, 30, 30}, plot::LegendEntry::Mark::line}};
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
