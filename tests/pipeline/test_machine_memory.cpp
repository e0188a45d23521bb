// pipeline::available_memory_bytes and memory_budget_bytes: the machine's memory as the jobs plan with it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/pipeline/machine_memory.hpp"

namespace seqtopo::pipeline {
namespace {

TEST(Memory, TheMachineIsRead) {
  const auto available = available_memory_bytes();
  if (available) {
    EXPECT_GT(*available, 0U);  // Linux: /proc/meminfo
  }
  const auto budget = memory_budget_bytes();
  if (budget && available) {
    EXPECT_GE(*budget, *available);  // MemTotal, not what is free
  }
}

// SEQTOPO_MEMORY_LIMIT lowers what is available (a shared machine, a test); it never raises it, a bad value names
// the variable, and a huge one does not wrap to a tiny limit.
TEST(Memory, LimitFromTheEnvironment) {
  const auto limited = [](const char* value) {
    ::setenv("SEQTOPO_MEMORY_LIMIT", value, 1);
    const auto available = available_memory_bytes();
    ::unsetenv("SEQTOPO_MEMORY_LIMIT");
    return available;
  };
  const auto machine = available_memory_bytes();
  for (const auto& [text, bytes] : std::vector<std::pair<const char*, std::size_t>>{{"150M", std::size_t{150} << 20U},
                                                                                    {"1.5g", std::size_t{3} << 29U},
                                                                                    {"4096", 4096},
                                                                                    {"2K", 2048},
                                                                                    {" 1 M ", std::size_t{1} << 20U},
                                                                                    {"0", 0}}) {
    SCOPED_TRACE(text);
    const auto available = limited(text);
    ASSERT_TRUE(available.has_value());
    EXPECT_LE(*available, bytes);
    // the machine's own figure moves between two readings; with twice the limit free the limit is what counts
    if (!machine || *machine / 2 > bytes) {
      EXPECT_EQ(*available, bytes);
    }
  }
  // far above the machine: the machine's figure, not a product wrapped to a small limit
  const auto huge = limited("1000000G");
  ASSERT_TRUE(huge.has_value());
  if (machine) {
    EXPECT_GT(*huge, *machine / 2);
  } else {
    EXPECT_EQ(*huge, std::size_t{1000000} << 30U);
  }
  for (const char* bad : {"lots", "-1", "nan", "1e300G", "12MB", "M", "1T"}) {
    SCOPED_TRACE(bad);
    ::setenv("SEQTOPO_MEMORY_LIMIT", bad, 1);
    try {
      (void)available_memory_bytes();
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), "SEQTOPO_MEMORY_LIMIT");
      EXPECT_NE(std::string(e.what()).find(std::string("got '") + bad + "'"), std::string::npos) << e.what();
    }
    ::unsetenv("SEQTOPO_MEMORY_LIMIT");
  }
}

}  // namespace
}  // namespace seqtopo::pipeline
