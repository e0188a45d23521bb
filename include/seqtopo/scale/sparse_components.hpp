#pragma once
// The sparse alignment (sparse_alignment.hpp) as independent tasks: its first fill splits the positive
// cells into connected components, each component is aligned on its own box by the exact engine, and
// a deterministic merge orders the results. Composed, the three steps are sparse_local_alignments();
// apart, they let the components run anywhere (other threads, other processes, other machines):
//
//   auto components = sparse_components_both(scores, config);
//   std::vector<std::vector<LocalAlignment>> aligned;             // aligned[k] from components[k]
//   for (const auto& c : components) aligned.push_back(align_component(scores, config, c));
//   auto result = merge_component_alignments_both(scores, config, components, std::move(aligned));
//   // result == sparse_local_alignments_both(scores, config)
//
// Where a component is aligned and in which order the components arrive at the merge do not change
// the result: the merge orders by the components' own `order`, never by arrival.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"

namespace seqtopo::scale {

// How the exact engine sees a component's box.
enum class SparseBoxKind {
  // Every cell of the box is inside the self band (or there is no band): aligned without a band.
  inside_band,
  // The component touches the self band's edge: the engine's band needs the diagonal, so the box is
  // the square on the diagonal spanning the component's rows and columns, aligned with the band.
  diagonal_square,
};

// Consecutive pass columns [pass_col, pass_col + length) of one row of a component.
struct SparseRun {
  std::uint32_t pass_col = 0, length = 0;
  friend bool operator==(const SparseRun&, const SparseRun&) = default;
};

// One connected component of the positive cells of a pass's first fill, whose best cell reaches the
// threshold. Pass coordinates: row i, and pass column t = j forward, t = cols - 1 - j reverse.
struct SparseComponent {
  align::Direction direction = align::Direction::forward;
  // Position among its pass's components, in the row-major order of their first cells (pass
  // coordinates): the merge's base order.
  std::size_t order = 0;
  // Bounding box of the cells, pass coordinates, half-open.
  std::size_t row_begin = 0, row_end = 0, pass_col_begin = 0, pass_col_end = 0;
  SparseBoxKind kind = SparseBoxKind::inside_band;
  // The box the exact engine aligns, original coordinates, half-open.
  std::size_t box_row_begin = 0, box_row_end = 0, box_col_begin = 0, box_col_end = 0;
  float best = 0;  // the component's largest H in the first fill
  // The cells, row by row, as the maximal runs of consecutive pass columns: row row_begin + r holds
  // runs[run_begin[r] .. run_begin[r + 1]), by increasing column, never touching (run_begin has
  // row_end - row_begin + 1 entries). Alignments that start on another component's cell inside the box
  // belong to that component and are dropped.
  std::vector<std::size_t> run_begin;
  std::vector<SparseRun> runs;

  std::size_t box_cells() const { return (box_row_end - box_row_begin) * (box_col_end - box_col_begin); }
  bool contains(std::size_t row, std::size_t pass_col) const;
  friend bool operator==(const SparseComponent&, const SparseComponent&) = default;
};

// The components of one pass (config.direction) that can reach config.threshold, by `order`.
// Throws std::invalid_argument like sparse_local_alignments(). stats: active cells, all components,
// aligned components and their box cells.
std::vector<SparseComponent> sparse_components(const SparseScores& scores, const align::AlignConfig& config,
                                               SparseAlignStats* stats = nullptr);
// Both passes (concurrently when threads > 1): the forward components, then the reverse ones.
std::vector<SparseComponent> sparse_components_both(const SparseScores& scores, const align::AlignConfig& config,
                                                    unsigned threads = 2, SparseAlignStats* stats = nullptr);

// The component's alignments in the order the exact engine takes them, in original indices. `config`
// is the one given to sparse_components (its direction is replaced by the component's).
std::vector<align::LocalAlignment> align_component(const SparseScores& scores, const align::AlignConfig& config,
                                                   const SparseComponent& component);

// One pass: aligned[k] = align_component(scores, config, components[k]), components in any order, all
// of config.direction (std::invalid_argument otherwise). The result is sparse_local_alignments()'s:
// by decreasing score, then a_begin, then b_begin; alignments of different components that tie on all
// three are ordered by the row-major position of the first maximal cell at the time each was taken, as
// the dense engine orders them (recomputed on the component's box for the tied alignments only); then
// config.max_alignments.
std::vector<align::LocalAlignment> merge_component_alignments(const SparseScores& scores,
                                                              const align::AlignConfig& config,
                                                              std::span<const SparseComponent> components,
                                                              std::vector<std::vector<align::LocalAlignment>> aligned);
// Both passes' components in any order: each pass merged as above, then the passes merged as
// local_alignments_both() merges them. The result is sparse_local_alignments_both()'s.
std::vector<align::LocalAlignment> merge_component_alignments_both(
    const SparseScores& scores, const align::AlignConfig& config, std::span<const SparseComponent> components,
    std::vector<std::vector<align::LocalAlignment>> aligned);

// Deals the components out to `ranks` workers: largest box first (box_cells, ties in input order), each
// to the worker with the fewest box cells so far (ties to the lowest worker). Returns the worker of
// each component. Throws std::invalid_argument when ranks = 0.
std::vector<std::size_t> deal_components(std::span<const SparseComponent> components, std::size_t ranks);

}  // namespace seqtopo::scale
