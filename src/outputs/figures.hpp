#pragma once
// How the static figures are framed (titles, axis labels, legends), shared by the files and the reports.
#include "seqtopo/pipeline/localize_pipeline.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/plot/matrix_image.hpp"

namespace seqtopo::outputs {

// similarity.png of `seqtopo map`: what was aligned, its axes, the colour bar's meaning, the overlays' legend.
plot::MatrixFigureConfig map_similarity_figure(const pipeline::MapRun& run);
// similarity.png of `seqtopo localize`: query frames (rows) x map frames (columns).
plot::MatrixFigureConfig localize_similarity_figure(const pipeline::LocalizeRun& run);

}  // namespace seqtopo::outputs
