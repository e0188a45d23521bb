#include "seqtopo/pipeline/machine_memory.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/parse_number.hpp"

namespace seqtopo::pipeline {
namespace {

std::optional<std::size_t> read_number(const char* path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word == "max") return std::nullopt;
  try {
    return static_cast<std::size_t>(std::stoull(word));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<std::size_t> meminfo(const std::string& which) {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  std::string unit;
  while (in >> key >> kib) {
    std::getline(in, unit);
    if (key == which) return kib * 1024;
  }
  return std::nullopt;
}

std::optional<std::size_t> mem_available() { return meminfo("MemAvailable:"); }

// A limit the user sets (a shared machine, a test): SEQTOPO_MEMORY_LIMIT=BYTES, with an optional K, M or G.
std::optional<std::size_t> user_limit() {
  const char* limit = std::getenv("SEQTOPO_MEMORY_LIMIT");
  if (limit == nullptr || *limit == '\0') return std::nullopt;
  {
    std::string text = limit;
    text.erase(0, text.find_first_not_of(" \t"));
    text.erase(text.find_last_not_of(" \t") + 1);
    std::size_t scale = 1;
    const char unit = text.empty() ? '\0' : static_cast<char>(std::toupper(static_cast<unsigned char>(text.back())));
    if (unit == 'K' || unit == 'M' || unit == 'G') {
      scale = std::size_t{1} << (unit == 'K' ? 10U : unit == 'M' ? 20U : 30U);
      text.pop_back();
    }
    // At most 2^60 bytes in any unit: the product stays far below SIZE_MAX (never wraps to a small limit).
    double value = 0;
    try {
      value = parse_number<double>("SEQTOPO_MEMORY_LIMIT", text,
                                   {.min = 0, .max = std::ldexp(1.0, 60) / static_cast<double>(scale)});
    } catch (const InputError&) {
      throw InputError("SEQTOPO_MEMORY_LIMIT",
                       "expected a number of bytes >= 0, optionally with K, M or G (at most "
                       "2^60 bytes), got '" +
                           std::string(limit) + "'");
    }
    return static_cast<std::size_t>(value * static_cast<double>(scale));
  }
}

}  // namespace

std::optional<std::size_t> memory_budget_bytes() {
  std::optional<std::size_t> budget = meminfo("MemTotal:");
  if (const auto limit = user_limit()) budget = budget ? std::min(*budget, *limit) : *limit;
  if (const auto cgroup = read_number("/sys/fs/cgroup/memory.max"))
    budget = budget ? std::min(*budget, *cgroup) : *cgroup;
  return budget;
}

std::optional<std::size_t> available_memory_bytes() {
  std::optional<std::size_t> available = mem_available();
  if (const auto limit = user_limit()) available = available ? std::min(*available, *limit) : *limit;
  // A container's limit is often far below the machine's free memory (cgroup v2 files).
  const auto limit = read_number("/sys/fs/cgroup/memory.max");
  if (limit) {
    const std::size_t used = read_number("/sys/fs/cgroup/memory.current").value_or(0);
    const std::size_t left = *limit > used ? *limit - used : 0;
    available = available ? std::min(*available, left) : left;
  }
  return available;
}

}  // namespace seqtopo::pipeline
