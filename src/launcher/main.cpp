// seqtopo: starts the command-line program, seqtopo-main (beside this file in a build tree or a Python wheel,
// in ../libexec/seqtopo/ when installed), with the same arguments, standard streams and process id.
//
// Why a launcher: the commands that hold N x N matrices fault them in 4 KiB pages unless malloc asks the
// kernel for transparent huge pages (madvise), and glibc does that only when GLIBC_TUNABLES says so when the
// process starts. This small program, which links nothing but the C and C++ runtimes, adds
// glibc.malloc.hugetlb=1 for them and starts seqtopo-main, whose start-up (its image and video libraries) is
// the expensive one. On the 3,600 Nordland frames `seqtopo map` took 195,000 page faults and 3.9 s, with huge
// pages 36,000 and 2.7 s (BENCHMARK.md). A GLIBC_TUNABLES that already names glibc.malloc.hugetlb (=0 turns this off)
// is left as it is, and so is the environment of `--online`, whose frames should not wait for the kernel to compact
// memory into huge pages.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <string_view>
#include <system_error>

namespace {

namespace fs = std::filesystem;

bool holds_matrices(int argc, char** argv) {
  static constexpr std::string_view heavy[] = {"map", "localize", "similarity", "bench"};
  if (argc < 2 || std::find(std::begin(heavy), std::end(heavy), std::string_view(argv[1])) == std::end(heavy)) {
    return false;
  }
  return std::none_of(argv + 2, argv + argc, [](const char* a) { return std::string_view(a) == "--online"; });
}

void ask_for_huge_pages() {
#if !defined(__SANITIZE_ADDRESS__)  // AddressSanitizer's allocator reads no glibc tunables
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string before = tunables == nullptr ? "" : tunables;
  if (before.find("glibc.malloc.hugetlb") != std::string::npos) return;
  const std::string after = (before.empty() ? "" : before + ":") + "glibc.malloc.hugetlb=1";
  ::setenv("GLIBC_TUNABLES", after.c_str(), 1);
#endif
}

// The folder of this executable: /proc/self/exe, else argv[0] when it names a path.
fs::path own_folder(const char* argv0) {
  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec && argv0 != nullptr && std::strchr(argv0, '/') != nullptr) self = fs::absolute(argv0, ec);
  return self.parent_path();
}

}  // namespace

int main(int argc, char** argv) {
  // The run's clock starts here (cli/progress.cpp), not at the process's start: a script that builds seqtopo and
  // then execs it started this process long before.
  timespec now{};
  clock_gettime(CLOCK_BOOTTIME, &now);
  const std::string started = std::to_string(static_cast<unsigned long long>(now.tv_sec) * 1000000000ULL +
                                             static_cast<unsigned long long>(now.tv_nsec));
  ::setenv("SEQTOPO_STARTED_NS", started.c_str(), 1);
  const fs::path folder = own_folder(argc > 0 ? argv[0] : nullptr);
  fs::path program;
  for (const fs::path& candidate : {folder / "seqtopo-main", folder / ".." / "libexec" / "seqtopo" / "seqtopo-main"}) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      program = candidate;
      break;
    }
  }
  if (program.empty()) {
    std::cerr << "seqtopo: error: " << (folder / "seqtopo-main").string()
              << ": the command-line program is missing (reinstall seqtopo)\n";
    return 1;
  }
  if (holds_matrices(argc, argv)) ask_for_huge_pages();
  ::execv(program.c_str(), argv);
  std::cerr << "seqtopo: error: " << program.string() << ": cannot start: " << std::strerror(errno) << "\n";
  return 1;
}
