#include "seqtopo/significance/online_islands.hpp"

namespace seqtopo::significance {

std::size_t IslandRow::slot(std::uint64_t start) const {
  std::uint64_t x = start * 0x9E3779B97F4A7C15ULL;  // Fibonacci hashing: the high bits mix every bit of the key
  x ^= x >> 29U;
  return static_cast<std::size_t>(x) & (slots_.size() - 1);
}

const Island* IslandRow::find(std::uint64_t start) const {
  if (slots_.empty()) return nullptr;
  for (std::size_t s = slot(start);; s = (s + 1) & (slots_.size() - 1)) {
    const std::uint32_t at = slots_[s];
    if (at == 0) return nullptr;
    if (islands[at - 1].first == start) return &islands[at - 1].second;
  }
}

Island* IslandRow::find(std::uint64_t start) {
  return const_cast<Island*>(static_cast<const IslandRow&>(*this).find(start));
}

Island& IslandRow::add(std::uint64_t start, const Island& island) {
  islands.emplace_back(start, island);
  std::size_t s = slot(start);
  while (slots_[s] != 0) s = (s + 1) & (slots_.size() - 1);
  slots_[s] = static_cast<std::uint32_t>(islands.size());
  used_.push_back(s);
  return islands.back().second;
}

void IslandRow::clear(std::size_t bound) {
  islands.clear();
  if (slots_.size() < 2 * bound) {
    std::size_t size = 16;
    while (size < 2 * bound) size *= 2;
    slots_.assign(size, 0);
  } else {
    for (const std::size_t s : used_) slots_[s] = 0;
  }
  used_.clear();
}

}  // namespace seqtopo::significance
