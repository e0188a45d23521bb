#include "seqtopo/core/huge_pages.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace seqtopo {

void advise_huge_pages(const void* data, std::size_t bytes) {
  // Below two huge pages the range holds at most one whole 2 MiB page: not worth a system call.
  constexpr std::size_t kHugePage = std::size_t{2} << 20U;
  if (data == nullptr || bytes < 2 * kHugePage) return;
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + page - 1) / page * page;  // madvise wants page-aligned bounds
  const std::uintptr_t last = (begin + bytes) / page * page;
  // Advice only: an old kernel or one without huge pages refuses it (EINVAL), and the buffer works as before.
  (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

}  // namespace seqtopo
