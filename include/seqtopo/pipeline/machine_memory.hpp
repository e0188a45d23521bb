#pragma once
// The machine's memory, as the jobs plan with it: the one place that reads /proc/meminfo, the cgroup's limit and
// SEQTOPO_MEMORY_LIMIT. The algorithms take a byte budget (similarity::MatrixConfig::memory_budget) instead.
#include <cstddef>
#include <optional>

namespace seqtopo::pipeline {

// Memory this process may still use [bytes]: the smallest of MemAvailable (/proc/meminfo), the cgroup limit minus
// current use, and the environment variable SEQTOPO_MEMORY_LIMIT (bytes, or with a K, M or G suffix; a bad value
// throws InputError naming it); nullopt when none can be read.
std::optional<std::size_t> available_memory_bytes();
// The memory a run may plan for, independent of what other processes use at the moment (so that a choice made
// from it, such as the map's engine, is the same on every run on this machine): the smallest of MemTotal, the
// cgroup limit and SEQTOPO_MEMORY_LIMIT; nullopt when none can be read.
std::optional<std::size_t> memory_budget_bytes();

}  // namespace seqtopo::pipeline
