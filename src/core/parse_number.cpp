#include "seqtopo/core/parse_number.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo {
namespace {

// The shortest text that reads back as v ("1048576", not "1.04858e+06"): the range an error states is exact.
std::string number_text(double v) {
  std::array<char, 32> text{};
  const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), v);
  return error == std::errc{} ? std::string(text.data(), end) : std::string("?");
}

}  // namespace

std::string NumberLimits::describe(bool integer) const {
  const std::string what = integer ? "an integer" : "a finite number";
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max) {
    return what + " in " + (min_exclusive ? "(" : "[") + number_text(min) + ", " + number_text(max) +
           (max_exclusive ? ")" : "]");
  }
  if (has_min) return what + (min_exclusive ? " > " : " >= ") + number_text(min);
  if (has_max) return what + (max_exclusive ? " < " : " <= ") + number_text(max);
  return what;
}

template <typename T>
T parse_number(std::string_view subject, std::string_view text, const NumberLimits& limits) {
  constexpr bool integer = std::is_integral_v<T>;
  const auto fail = [&]() -> T {
    throw InputError(std::string(subject),
                     "expected " + limits.describe(integer) + ", got '" + std::string(text) + "'");
  };
  std::string_view t = text;
  while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
  while (!t.empty() && (t.back() == ' ' || t.back() == '\t' || t.back() == '\r')) t.remove_suffix(1);
  if (!t.empty() && t.front() == '+') {
    t.remove_prefix(1);
    if (!t.empty() && t.front() == '-') return fail();  // "+-1": one sign at most
  }
  if (t.empty() || t.front() == '+' || (std::is_unsigned_v<T> && t.front() == '-')) return fail();
  T value{};
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (error != std::errc{} || end != t.data() + t.size()) return fail();
  if constexpr (!integer) {
    if (!std::isfinite(value)) return fail();
  }
  const auto v = static_cast<double>(value);
  if (limits.min_exclusive ? !(v > limits.min) : !(v >= limits.min)) return fail();
  if (limits.max_exclusive ? !(v < limits.max) : !(v <= limits.max)) return fail();
  return value;
}

template float parse_number<float>(std::string_view, std::string_view, const NumberLimits&);
template double parse_number<double>(std::string_view, std::string_view, const NumberLimits&);
template int parse_number<int>(std::string_view, std::string_view, const NumberLimits&);
template unsigned parse_number<unsigned>(std::string_view, std::string_view, const NumberLimits&);
template long parse_number<long>(std::string_view, std::string_view, const NumberLimits&);
template unsigned long parse_number<unsigned long>(std::string_view, std::string_view, const NumberLimits&);
template unsigned long long parse_number<unsigned long long>(std::string_view, std::string_view, const NumberLimits&);

}  // namespace seqtopo
