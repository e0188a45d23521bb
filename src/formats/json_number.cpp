#include "seqtopo/formats/json_number.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace seqtopo::formats {

double json_number(float value) {
  if (!std::isfinite(value)) return static_cast<double>(value);  // JSON has no such number: the library writes null
  return std::stod(fmt::format("{}", value));
}

}  // namespace seqtopo::formats
