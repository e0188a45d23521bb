#include "wire.hpp"

#include <bit>
#include <stdexcept>

namespace seqtopo::mpi {
namespace {

// Reads words in order; a short or inconsistent message is a bug, not a user error.
class Reader {
 public:
  explicit Reader(std::span<const std::uint64_t> words) : words_(words) {}
  std::uint64_t next() {
    if (at_ >= words_.size()) throw std::logic_error("seqtopo-mpi: truncated message");
    return words_[at_++];
  }
  std::size_t size() { return static_cast<std::size_t>(next()); }
  bool done() const { return at_ == words_.size(); }

 private:
  std::span<const std::uint64_t> words_;
  std::size_t at_ = 0;
};

}  // namespace

ScoresWire encode_scores(const scale::SparseScores& scores) {
  ScoresWire w;
  w.header = {scores.rows(), scores.cols(), std::bit_cast<std::uint32_t>(scores.background())};
  w.row_counts.reserve(scores.rows());
  w.columns.reserve(scores.entries());
  w.values.reserve(scores.entries());
  for (std::size_t i = 0; i < scores.rows(); ++i) {
    const auto cols = scores.row_columns(i);
    const auto vals = scores.row_values(i);
    w.row_counts.push_back(cols.size());
    w.columns.insert(w.columns.end(), cols.begin(), cols.end());
    w.values.insert(w.values.end(), vals.begin(), vals.end());
  }
  return w;
}

scale::SparseScores decode_scores(const ScoresWire& w) {
  if (w.header.size() != 3 || w.row_counts.size() != w.header[0] || w.columns.size() != w.values.size()) {
    throw std::logic_error("seqtopo-mpi: inconsistent sparse scores message");
  }
  std::vector<scale::SparseEntry> entries;
  entries.reserve(w.columns.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < w.row_counts.size(); ++i) {
    for (std::uint64_t c = 0; c < w.row_counts[i]; ++c, ++k) {
      entries.push_back({static_cast<std::uint32_t>(i), w.columns.at(k), w.values.at(k)});
    }
  }
  return {static_cast<std::size_t>(w.header[0]), static_cast<std::size_t>(w.header[1]),
          std::bit_cast<float>(static_cast<std::uint32_t>(w.header[2])), std::move(entries)};
}

std::vector<std::uint64_t> encode_components(std::span<const scale::SparseComponent* const> components) {
  std::vector<std::uint64_t> w{components.size()};
  for (const scale::SparseComponent* c : components) {
    w.insert(w.end(), {c->direction == align::Direction::forward ? 0U : 1U, c->order, c->row_begin, c->row_end,
                       c->pass_col_begin, c->pass_col_end, c->kind == scale::SparseBoxKind::inside_band ? 0U : 1U,
                       c->box_row_begin, c->box_row_end, c->box_col_begin, c->box_col_end,
                       std::bit_cast<std::uint32_t>(c->best), c->run_begin.size(), c->runs.size()});
    w.insert(w.end(), c->run_begin.begin(), c->run_begin.end());
    // a run in one word: its first column above its length
    for (const scale::SparseRun& r : c->runs) w.push_back(std::uint64_t{r.pass_col} << 32 | r.length);
  }
  return w;
}

std::vector<scale::SparseComponent> decode_components(std::span<const std::uint64_t> words) {
  Reader in(words);
  std::vector<scale::SparseComponent> out(in.size());
  for (scale::SparseComponent& c : out) {
    c.direction = in.next() == 0 ? align::Direction::forward : align::Direction::reverse;
    c.order = in.size();
    c.row_begin = in.size();
    c.row_end = in.size();
    c.pass_col_begin = in.size();
    c.pass_col_end = in.size();
    c.kind = in.next() == 0 ? scale::SparseBoxKind::inside_band : scale::SparseBoxKind::diagonal_square;
    c.box_row_begin = in.size();
    c.box_row_end = in.size();
    c.box_col_begin = in.size();
    c.box_col_end = in.size();
    c.best = std::bit_cast<float>(static_cast<std::uint32_t>(in.next()));
    c.run_begin.resize(in.size());
    c.runs.resize(in.size());
    for (auto& b : c.run_begin) b = in.size();
    for (auto& r : c.runs) {
      const std::uint64_t word = in.next();
      r = {static_cast<std::uint32_t>(word >> 32), static_cast<std::uint32_t>(word)};
    }
  }
  if (!in.done()) throw std::logic_error("seqtopo-mpi: trailing words in a components message");
  return out;
}

AlignmentsWire encode_alignments(const std::vector<std::vector<align::LocalAlignment>>& per_component) {
  AlignmentsWire w;
  w.words.push_back(per_component.size());
  for (const auto& list : per_component) {
    w.words.push_back(list.size());
    for (const align::LocalAlignment& a : list) {
      w.scores.push_back(a.score);
      w.words.insert(w.words.end(), {a.direction == align::Direction::forward ? 0U : 1U, a.a_begin, a.a_end, a.b_begin,
                                     a.b_end, a.pairs.size()});
      for (const auto& [i, j] : a.pairs) w.words.insert(w.words.end(), {i, j});
    }
  }
  return w;
}

std::vector<std::vector<align::LocalAlignment>> decode_alignments(const AlignmentsWire& w) {
  Reader in(w.words);
  std::vector<std::vector<align::LocalAlignment>> out(in.size());
  std::size_t score = 0;
  for (auto& list : out) {
    list.resize(in.size());
    for (align::LocalAlignment& a : list) {
      a.score = w.scores.at(score++);
      a.direction = in.next() == 0 ? align::Direction::forward : align::Direction::reverse;
      a.a_begin = in.size();
      a.a_end = in.size();
      a.b_begin = in.size();
      a.b_end = in.size();
      a.pairs.resize(in.size());
      for (auto& [i, j] : a.pairs) {
        i = in.size();
        j = in.size();
      }
    }
  }
  if (!in.done() || score != w.scores.size()) {
    throw std::logic_error("seqtopo-mpi: trailing data in an alignments message");
  }
  return out;
}

}  // namespace seqtopo::mpi
