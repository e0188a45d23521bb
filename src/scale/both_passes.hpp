#pragma once
// The forward and the reverse pass of one sparse step, concurrently when threads > 1, with their
// statistics added up. Private to src/scale.
#include <algorithm>
#include <future>
#include <utility>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"

namespace seqtopo::scale::detail {

// pass(config, stats) for config's forward and reverse direction; returns (forward, reverse).
template <typename Pass>
auto both_passes(const align::AlignConfig& config, unsigned threads, SparseAlignStats* stats, Pass pass) {
  align::AlignConfig forward = config, reverse = config;
  forward.direction = align::Direction::forward;
  reverse.direction = align::Direction::reverse;
  SparseAlignStats fs, rs;
  decltype(pass(forward, &fs)) fwd, rev;
  if (threads > 1) {
    auto rev_future = std::async(std::launch::async, [&] { return pass(reverse, &rs); });
    fwd = pass(forward, &fs);
    rev = rev_future.get();
  } else {
    fwd = pass(forward, &fs);
    rev = pass(reverse, &rs);
  }
  if (stats != nullptr) {
    stats->active_cells = fs.active_cells + rs.active_cells;
    stats->components = fs.components + rs.components;
    stats->aligned_components = fs.aligned_components + rs.aligned_components;
    stats->box_cells = fs.box_cells + rs.box_cells;
    stats->largest_box_cells = std::max(fs.largest_box_cells, rs.largest_box_cells);
  }
  return std::make_pair(std::move(fwd), std::move(rev));
}

}  // namespace seqtopo::scale::detail
