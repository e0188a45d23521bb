#pragma once
// One parser for every number a user types (command-line options, config files): the whole text must be
// one decimal number of the target type, finite, inside its limits; no trailing characters, no sign on an
// unsigned type (so "-1" never wraps to 2^64 - 1). A failure throws InputError naming the option:
//   parse_number<float>("--gap", "nan", {.min = 0})  ->  "--gap: expected a finite number >= 0, got 'nan'"
#include <limits>
#include <string>
#include <string_view>

namespace seqtopo {

struct NumberLimits {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;  // true: the value must be > min (else >= min)
  bool max_exclusive = false;
  // "a number > 0", "an integer in [1, 64]", ...: what the error message says the option expects.
  std::string describe(bool integer) const;
};

// T is float, double, int, unsigned, long, std::size_t, ... Leading and trailing spaces are ignored.
template <typename T>
T parse_number(std::string_view subject, std::string_view text, const NumberLimits& limits = {});

extern template float parse_number<float>(std::string_view, std::string_view, const NumberLimits&);
extern template double parse_number<double>(std::string_view, std::string_view, const NumberLimits&);
extern template int parse_number<int>(std::string_view, std::string_view, const NumberLimits&);
extern template unsigned parse_number<unsigned>(std::string_view, std::string_view, const NumberLimits&);
extern template long parse_number<long>(std::string_view, std::string_view, const NumberLimits&);
extern template unsigned long parse_number<unsigned long>(std::string_view, std::string_view, const NumberLimits&);
extern template unsigned long long parse_number<unsigned long long>(std::string_view, std::string_view,
                                                                    const NumberLimits&);

}  // namespace seqtopo
