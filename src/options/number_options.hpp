#pragma once
// Numeric options of every command of both command-line programs (seqtopo, seqtopo-mpi), parsed by the one number
// parser (core/parse_number.hpp) while the command line is read: finite, in range, no trailing characters, no
// unsigned wrap-around, the option named in the error, and all of it before any work starts or any output folder
// is made.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <type_traits>

#include "seqtopo/core/parse_number.hpp"

namespace seqtopo::cli {

namespace detail {

// The option's first long name ("--gap" of "--gap,-g"), the subject of its errors.
inline std::string option_subject(const std::string& names) {
  std::string first = names.substr(0, names.find(','));
  return first;
}

template <typename T>
std::string number_type_name() {
  if constexpr (std::is_floating_point_v<T>) return "FLOAT";
  if constexpr (std::is_unsigned_v<T>) return "UINT";
  return "INT";
}

}  // namespace detail

// A validator for options registered with app.add_option: the text must parse as a T within `limits`.
template <typename T>
CLI::Validator number_check(NumberLimits limits) {
  return CLI::Validator(
      [limits](std::string& text) -> std::string {
        try {
          (void)parse_number<T>("", text, limits);
        } catch (const std::exception& e) {
          return e.what();
        }
        return {};
      },
      "", "");
}

// `names` takes a number into `target`; the help shows its current value as the default.
template <typename T>
CLI::Option* add_number(CLI::App& app, const std::string& names, T& target, NumberLimits limits,
                        const std::string& help) {
  const std::string subject = detail::option_subject(names);
  auto* option = app.add_option_function<std::string>(
      names, [&target, subject, limits](const std::string& text) { target = parse_number<T>(subject, text, limits); },
      help);
  std::ostringstream shown;
  shown << target;
  return option->type_name(detail::number_type_name<T>())
      ->default_str(shown.str())
      ->check(number_check<T>(limits).name("number"));
}

// The same for an option without a default (nullopt until given).
template <typename T>
CLI::Option* add_number(CLI::App& app, const std::string& names, std::optional<T>& target, NumberLimits limits,
                        const std::string& help) {
  const std::string subject = detail::option_subject(names);
  return app
      .add_option_function<std::string>(
          names,
          [&target, subject, limits](const std::string& text) { target = parse_number<T>(subject, text, limits); },
          help)
      ->type_name(detail::number_type_name<T>())
      ->check(number_check<T>(limits).name("number"));
}

// A number, or `keyword` (e.g. "none", "auto"), which sets `target` to nullopt and `keyword_given` to true.
template <typename T>
CLI::Option* add_number_or(CLI::App& app, const std::string& names, std::optional<T>& target,
                           const std::string& keyword, bool& keyword_given, NumberLimits limits,
                           const std::string& help) {
  const std::string subject = detail::option_subject(names);
  return app
      .add_option_function<std::string>(
          names,
          [&target, &keyword_given, subject, keyword, limits](const std::string& text) {
            keyword_given = text == keyword;
            if (keyword_given) {
              target.reset();
            } else {
              target = parse_number<T>(subject, text, limits);
            }
          },
          help)
      ->type_name(detail::number_type_name<T>() + "|" + keyword)
      ->check(CLI::Validator(
          [keyword, limits](std::string& text) -> std::string {
            if (text == keyword) return {};
            const std::string error = number_check<T>(limits)(text);
            return error.empty() ? error
                                 : error.substr(0, error.rfind(", got")) + " or '" + keyword + "', got '" + text + "'";
          },
          "", "number"));
}

// Every option of `app` and its subcommands whose type is a number (FLOAT, INT, UINT, also in lists) gets the
// parser's checks (finite, whole text, no sign on an unsigned type) unless it already has them: the net under
// options registered with plain app.add_option.
inline void check_all_numeric_options(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    try {
      (void)option->get_validator("number");  // registered by add_number with its own limits
      continue;
    } catch (const CLI::OptionNotFound&) {
    }
    const std::string type = option->get_type_name();
    // "FLOAT", "UINT:POSITIVE", ...; not "FLOAT|none" (add_number_or parses its own text).
    const auto is = [&](const std::string& name) {
      return type.rfind(name, 0) == 0 &&
             (type.size() == name.size() || type[name.size()] == ':' || type[name.size()] == ' ');
    };
    if (is("FLOAT")) {
      option->check(number_check<double>({}).name("number"));
    } else if (is("UINT")) {
      option->check(number_check<unsigned long long>({}).name("number"));
    } else if (is("INT")) {
      option->check(number_check<long>({}).name("number"));
    }
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_all_numeric_options(*sub);
}

// The number check of `option` (registered by add_number / add_number_or or check_all_numeric_options), or
// nullptr when the option does not take a number: config files check their values with it.
inline CLI::Validator* find_number_check(CLI::Option& option) {
  try {
    return option.get_validator("number");
  } catch (const CLI::OptionNotFound&) {
    return nullptr;
  }
}

// Limits used by many options.
inline constexpr NumberLimits kPositive{.min = 0, .min_exclusive = true};
inline constexpr NumberLimits kNonNegative{.min = 0};
inline constexpr NumberLimits kAtLeastOne{.min = 1};
inline constexpr NumberLimits kAnyFinite{};
inline constexpr NumberLimits kProbability{.min = 0, .max = 1};
// Worker threads: 0 = every core; resolve_threads() never uses more than the cores.
inline constexpr NumberLimits kThreads{.min = 0, .max = 4096};
// A separation in places or frames: at most 10^9, far beyond any sequence, so that its value in frames (places
// times frames per place) cannot wrap.
inline constexpr NumberLimits kSeparation{.min = 1, .max = 1e9};

}  // namespace seqtopo::cli
