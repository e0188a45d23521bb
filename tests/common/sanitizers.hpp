#pragma once
// The sanitizer pass (scripts/test.sh sanitize) runs the suite several times slower than the Release build. A test
// whose code paths the other tests already take at small sizes, and whose own cost is its size or its many seeds (a
// statistical check over many sequences, a long synthetic route, a large figure), skips itself in that pass only;
// the Release pass runs it.
#include <gtest/gtest.h>

#if defined(__SANITIZE_ADDRESS__)
#define SEQTOPO_SKIP_UNDER_SANITIZERS(why) \
  GTEST_SKIP() << "skipped under the sanitizers (the Release pass runs it): " << why
#else
#define SEQTOPO_SKIP_UNDER_SANITIZERS(why) static_cast<void>(0)
#endif
