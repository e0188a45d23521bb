#pragma once
// The blanks around a field or line of the text formats read here (spaces, tabs, a Windows line end's '\r').
#include <string_view>

namespace seqtopo::formats::detail {

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace seqtopo::formats::detail
