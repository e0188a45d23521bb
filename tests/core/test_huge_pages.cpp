// The library's large matrices ask for transparent huge pages themselves (core/huge_pages.hpp), so that a program
// linking it (the Python module) gets them without the command-line launcher's GLIBC_TUNABLES.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo {
namespace {

// The VmFlags line of the mapping of this process that holds `address` (/proc/self/smaps), "" when none does.
std::string vm_flags_at(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (line.find(':') > line.find(' ') && (range >> std::hex >> begin >> dash >> end) && dash == '-') {
      inside = begin <= at && at < end;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return "";
}

bool kernel_has_huge_pages() { return std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"); }

TEST(HugePages, LargeMatrixIsAdvisedBeforeItIsFilled) {
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "this kernel has no transparent huge pages";
  const DenseMatrix<float> m(2048, 2048, 1.0F);  // 16 MiB, an N x N similarity matrix of 2,048 frames
  const std::string flags = vm_flags_at(m.values.data() + m.values.size() / 2);
  ASSERT_FALSE(flags.empty());
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;  // VM_HUGEPAGE: madvise(MADV_HUGEPAGE) was called
  EXPECT_EQ(m(2047, 2047), 1.0F);
}

TEST(HugePages, SmallMatrixIsLeftAlone) {
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "this kernel has no transparent huge pages";
  const DenseMatrix<float> m(64, 64, 2.0F);  // 16 KiB: no whole huge page in it
  const std::string flags = vm_flags_at(m.values.data());
  ASSERT_FALSE(flags.empty());
  EXPECT_EQ(flags.find(" hg"), std::string::npos) << flags;
  EXPECT_EQ(m(63, 63), 2.0F);
}

}  // namespace
}  // namespace seqtopo
