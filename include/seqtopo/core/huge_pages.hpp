#pragma once
// Transparent huge pages for the library's own large buffers (the N x N matrices): 2 MiB pages instead of
// 4 KiB ones, so that filling a 3,600 x 3,600 matrix takes a few hundred page faults instead of a few thousand per
// matrix. The command-line launcher also asks glibc for them (src/launcher/main.cpp), but only for its own
// process: a program that links the library, the Python module among them, gets them from here.
#include <cstddef>

namespace seqtopo {

// Asks the kernel (madvise MADV_HUGEPAGE) to back the whole pages inside [data, data + bytes) with huge pages
// when the range is large enough to hold one; a no-op for smaller ranges and where the kernel has no
// transparent huge pages. Call it before the memory is first written: pages already faulted in stay small.
void advise_huge_pages(const void* data, std::size_t bytes);

}  // namespace seqtopo
