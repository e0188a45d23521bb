#pragma once
// ASCII lower case, for names compared without regard to case (file extensions, format names).
#include <algorithm>
#include <cctype>
#include <string>

namespace seqtopo {

inline std::string lower_case(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace seqtopo
