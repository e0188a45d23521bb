#pragma once
// What a reader's InputError says, as one line: "subject: message", or "no error" when `f` returns.
#include <functional>
#include <string>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo::test_support {

inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.subject() + ": " + e.what();
  }
  return "no error";
}

}  // namespace seqtopo::test_support
