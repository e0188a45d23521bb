#pragma once
// How `seqtopo map --online` is written at its end (INTERFACE.md): online_loop_closures.csv (the loop closures
// standing after the last frame), online.json (frames, latencies, events by kind, the significance and the
// contrast offset the run ended with, the metrics), and with the offline map its files and report. events.jsonl is
// the caller's: it is written as the frames arrive.
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/pipeline/online_map.hpp"

namespace seqtopo::outputs {

void write_online_map_outputs(const pipeline::OnlineMapRun& run, const mapping::OnlineMapConfig& config,
                              io::OutputDirectory& out);

// The q-quantile of `values` (the smallest value at least a fraction q of them do not exceed; 0 when empty).
double quantile(std::vector<double> values, double q);

}  // namespace seqtopo::outputs
