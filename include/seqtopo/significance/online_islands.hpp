#pragma once
// The islands of a local alignment table that grows one row at a time (the island method of Olsen, Bundschuh & Hwa
// 1999; Altschul et al. 2001): the cells that share one start cell form an island, its score is its largest value,
// and once no cell of the newest row carries its start it has died and its score is final (cells descend only from
// the row before and their own row). In the logarithmic phase the number of chance islands scoring at least s is
// about K * area * exp(-lambda s), so the best dead islands are a sample for the extreme-value fit
// (score_statistics.hpp: fit_declumped_scores). Used by the online mapper (mapping/online_mapper.hpp).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

namespace seqtopo::significance {

struct Island {
  float best = 0;
  std::size_t i = 0, j = 0;  // the cell of its best value (the first reached)
};

// The islands one row carries, in the order the row first reaches them, by start cell (open addressing). A row
// holds runs of cells of one start: one probe per run, into tables kept from row to row, costs a fraction of a hash
// map's lookup and node allocation per cell.
class IslandRow {
 public:
  std::vector<std::pair<std::uint64_t, Island>> islands;
  Island* find(std::uint64_t start);
  const Island* find(std::uint64_t start) const;
  Island& add(std::uint64_t start, const Island& island);  // a start not in the row yet
  void clear(std::size_t bound);                           // empty, for at most `bound` islands

 private:
  std::size_t slot(std::uint64_t start) const;
  std::vector<std::uint32_t> slots_;  // index + 1 into islands, 0: empty; a power of two of at least 2 x bound
  std::vector<std::size_t> used_;     // the slots filled
};

// The islands of one table, row after row.
class OnlineIslands {
 public:
  // The table's newest row, `frame`: its values and the start cell of the path attaining each (the same length;
  // cells <= 0 belong to no island). Each island the row no longer carries is passed to died(start, island), in the
  // order the previous row first reached them.
  template <typename Died>
  void advance(std::span<const float> row, std::span<const std::uint64_t> starts, std::size_t frame, Died&& died) {
    // Each start's best cell of the row, the first of equal ones; a run of cells of one start is looked up once.
    next_.clear(row.size());
    Island* run = nullptr;
    for (std::size_t j = 0; j < row.size(); ++j) {
      if (row[j] <= 0) {
        run = nullptr;
        continue;
      }
      if (run == nullptr || starts[j] != starts[j - 1]) {
        run = next_.find(starts[j]);
        if (run == nullptr) {
          run = &next_.add(starts[j], Island{row[j], frame, j});
          continue;
        }
      }
      if (row[j] > run->best) *run = {row[j], frame, j};
    }
    for (const auto& [start, island] : live_.islands) {
      if (Island* next = next_.find(start); next != nullptr) {
        if (island.best >= next->best) *next = island;
        continue;
      }
      died(start, island);
    }
    std::swap(live_, next_);
  }
  // The islands the newest row carries, with their best values so far.
  const IslandRow& live() const { return live_; }

 private:
  IslandRow live_, next_;
};

// The best `capacity` of a stream of (score, length) values, and how many were offered.
class BestIslands {
 public:
  explicit BestIslands(std::size_t capacity) : capacity_(capacity) {}
  // Whether the value is kept (it is among the best so far).
  bool offer(std::pair<double, double> value) {
    ++offered_;
    if (heap_.size() < capacity_) {
      heap_.push_back(value);
      std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
      return true;
    }
    if (!(value > heap_.front())) return false;
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    heap_.back() = value;
    std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
    return true;
  }
  void clear() {
    heap_.clear();
    offered_ = 0;
  }
  std::size_t offered() const { return offered_; }
  std::size_t size() const { return heap_.size(); }
  // The values kept, best first.
  std::vector<std::pair<double, double>> best() const {
    std::vector<std::pair<double, double>> out = heap_;
    std::sort(out.begin(), out.end(), std::greater<>());
    return out;
  }

 private:
  std::size_t capacity_;
  std::vector<std::pair<double, double>> heap_;  // a min-heap
  std::size_t offered_ = 0;
};

}  // namespace seqtopo::significance
