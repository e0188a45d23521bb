#include "seqtopo/scale/sparse_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <stdexcept>
#include <string>

#include "both_passes.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/scale/sparse_components.hpp"

namespace seqtopo::scale {

using align::AlignConfig;
using align::Direction;
using align::LocalAlignment;

SparseScores::SparseScores(std::size_t rows, std::size_t cols, float background, std::vector<SparseEntry> entries)
    : rows_(rows), cols_(cols), background_(background) {
  if (!std::isfinite(background)) throw std::invalid_argument("sparse scores: background must be finite");
  if (cols > std::numeric_limits<std::uint32_t>::max()) throw std::invalid_argument("sparse scores: too many columns");
  std::sort(entries.begin(), entries.end(),
            [](const SparseEntry& a, const SparseEntry& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  row_begin_.assign(rows + 1, 0);
  columns_.reserve(entries.size());
  values_.reserve(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const SparseEntry& e = entries[k];
    if (e.i >= rows || e.j >= cols) {
      throw std::invalid_argument("sparse scores: entry (" + std::to_string(e.i) + ", " + std::to_string(e.j) +
                                  ") outside a " + std::to_string(rows) + " x " + std::to_string(cols) + " matrix");
    }
    if (k > 0 && entries[k - 1].i == e.i && entries[k - 1].j == e.j) {
      throw std::invalid_argument("sparse scores: cell (" + std::to_string(e.i) + ", " + std::to_string(e.j) +
                                  ") listed twice");
    }
    if (!std::isfinite(e.score)) throw std::invalid_argument("sparse scores: scores must be finite");
    columns_.push_back(e.j);
    values_.push_back(e.score);
    ++row_begin_[e.i + 1];
  }
  for (std::size_t i = 0; i < rows; ++i) row_begin_[i + 1] += row_begin_[i];
}

std::span<const std::uint32_t> SparseScores::row_columns(std::size_t i) const {
  return {columns_.data() + row_begin_[i], row_begin_[i + 1] - row_begin_[i]};
}
std::span<const float> SparseScores::row_values(std::size_t i) const {
  return {values_.data() + row_begin_[i], row_begin_[i + 1] - row_begin_[i]};
}

float SparseScores::at(std::size_t i, std::size_t j) const {
  const auto cols = row_columns(i);
  const auto it = std::lower_bound(cols.begin(), cols.end(), j);
  if (it != cols.end() && *it == j) return row_values(i)[static_cast<std::size_t>(it - cols.begin())];
  return background_;
}

void SparseScores::read_row(std::size_t i, std::size_t j_begin, std::size_t j_end, float* out) const {
  std::fill(out, out + (j_end - j_begin), background_);
  const auto cols = row_columns(i);
  const auto vals = row_values(i);
  for (auto it = std::lower_bound(cols.begin(), cols.end(), j_begin); it != cols.end() && *it < j_end; ++it) {
    out[*it - j_begin] = vals[static_cast<std::size_t>(it - cols.begin())];
  }
}

align::ScoreSource SparseScores::source() const {
  return align::ScoreSource(
      rows_, cols_, [this](std::size_t i, std::size_t jb, std::size_t je, float* out) { read_row(i, jb, je, out); });
}

std::vector<LocalAlignment> sparse_local_alignments(const SparseScores& scores, const AlignConfig& config,
                                                    SparseAlignStats* stats) {
  SparseAlignStats local;
  const std::vector<SparseComponent> components = sparse_components(scores, config, &local);
  std::vector<std::vector<LocalAlignment>> aligned;
  aligned.reserve(components.size());
  for (const SparseComponent& c : components) aligned.push_back(align_component(scores, config, c));
  auto out = merge_component_alignments(scores, config, components, std::move(aligned));
  if (stats != nullptr) *stats = local;
  return out;
}

std::vector<LocalAlignment> sparse_local_alignments_both(const SparseScores& scores, AlignConfig config,
                                                         unsigned threads, SparseAlignStats* stats) {
  auto [fwd, rev] = detail::both_passes(config, threads, stats, [&](const AlignConfig& c, SparseAlignStats* st) {
    return sparse_local_alignments(scores, c, st);
  });
  return align::merge_directions(std::move(fwd), std::move(rev), config.max_alignments);
}

}  // namespace seqtopo::scale
