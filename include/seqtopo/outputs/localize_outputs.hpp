#pragma once
// How a localization run is written (INTERFACE.md, `seqtopo localize` outputs): matches.csv, similarity.png,
// and with ground truth metrics.json and pr_curve.png; latency.csv online; report.html over them.
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/report_options.hpp"
#include "seqtopo/pipeline/localize_pipeline.hpp"

namespace seqtopo::outputs {

// Every file but the report, staged in `out`. Returns the number of query frames "not in the map".
std::size_t write_localize_outputs(const pipeline::LocalizeRun& run, io::OutputDirectory& out);
// report.html from the staged files (localize_report.cpp), interactive as the map's (map_outputs.hpp).
ReportResult write_localize_report(const pipeline::LocalizeRun& run, io::OutputDirectory& out,
                                   const ReportOptions& options = {});

// Latency percentile p in [0, 1] of the online frames [s] (0 when there is none).
double latency_percentile(const pipeline::LocalizeRun& run, double p);

}  // namespace seqtopo::outputs
