// LD_PRELOAD shim for the fault tests: rename(2) calls whose destination is SEQTOPO_FAULT_TARGET fail or stall.
//   SEQTOPO_FAULT_MODE=fail   the call fails with EIO
//   SEQTOPO_FAULT_MODE=before the shim creates the file SEQTOPO_FAULT_MARK, sleeps SEQTOPO_FAULT_MS, then renames
//   SEQTOPO_FAULT_MODE=after  the shim renames, creates the mark, then sleeps
// (strace -e inject=... does the same where ptrace is allowed; containers often forbid it.)
#include <dlfcn.h>
#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace {

bool is_target(const char* path) {
  const char* target = std::getenv("SEQTOPO_FAULT_TARGET");
  return target != nullptr && path != nullptr && std::strcmp(path, target) == 0;
}

void mark_and_sleep() {
  if (const char* mark = std::getenv("SEQTOPO_FAULT_MARK")) {
    const int fd = ::open(mark, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) ::close(fd);
  }
  const char* ms = std::getenv("SEQTOPO_FAULT_MS");
  const long millis = ms != nullptr ? std::atol(ms) : 5000;
  timespec t{millis / 1000, (millis % 1000) * 1000000};
  while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
  }
}

// Runs `call` with the fault SEQTOPO_FAULT_MODE asks for when `to` is the target.
template <typename Call>
int with_fault(const char* to, Call call) {
  if (!is_target(to)) return call();
  const char* mode = std::getenv("SEQTOPO_FAULT_MODE");
  if (mode == nullptr) return call();
  if (std::strcmp(mode, "fail") == 0) {
    errno = EIO;
    return -1;
  }
  if (std::strcmp(mode, "before") == 0) mark_and_sleep();
  const int rc = call();
  const int saved = errno;
  if (std::strcmp(mode, "after") == 0) mark_and_sleep();
  errno = saved;
  return rc;
}

template <typename F>
F next(const char* name) {
  return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

int rename(const char* from, const char* to) {
  static const auto real = next<int (*)(const char*, const char*)>("rename");
  return with_fault(to, [&] { return real(from, to); });
}

int renameat(int from_dir, const char* from, int to_dir, const char* to) {
  static const auto real = next<int (*)(int, const char*, int, const char*)>("renameat");
  return with_fault(to, [&] { return real(from_dir, from, to_dir, to); });
}

int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned flags) {
  static const auto real = next<int (*)(int, const char*, int, const char*, unsigned)>("renameat2");
  return with_fault(to, [&] { return real(from_dir, from, to_dir, to, flags); });
}
}
