// The one number parser of every option and config value (core/parse_number.hpp): the whole text, one decimal
// number of the type, finite, in range, no sign on an unsigned type; the error names the option and the range.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/parse_number.hpp"

namespace seqtopo {
namespace {

template <typename T>
void expect_refused(const std::string& text, const NumberLimits& limits = {}) {
  try {
    const T value = parse_number<T>("--opt", text, limits);
    ADD_FAILURE() << "'" << text << "' gave " << value;
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), "--opt");
    EXPECT_NE(std::string(e.what()).find("got '" + text + "'"), std::string::npos) << e.what();
  }
}

const std::vector<std::string> kNeverNumbers = {
    "",      " ",    "nan",   "NaN", "-nan", "nan(1)", "inf", "-inf", "+inf",  "infinity", "INF", "3x",
    "1.5.2", "0x10", "0x1p3", "1e",  "1e+",  "--1",    "+-1", "-+1",  "++1",   "1 2",      "1,2", "1_000",
    "one",   "٣",    "1\n2",  "- 1", "e5",   ".",      "-",   "+",    "1e999", "-1e999"};

TEST(ParseNumber, RefusesEverythingThatIsNotOneFiniteNumber) {
  for (const auto& text : kNeverNumbers) {
    SCOPED_TRACE(text);
    expect_refused<float>(text);
    expect_refused<double>(text);
    expect_refused<int>(text);
    expect_refused<unsigned>(text);
    expect_refused<std::size_t>(text);
  }
}

TEST(ParseNumber, IntegersRefuseFractionsAndValuesBeyondTheType) {
  for (const std::string text : {"1.5", "1e3", "1.0", "2147483648", "-2147483649"}) expect_refused<int>(text);
  for (const std::string text : {"-1", "-0", "4294967296", "18446744073709551616"}) expect_refused<unsigned>(text);
  for (const std::string text : {"-1", "-0", "18446744073709551616", "99999999999999999999999"}) {
    expect_refused<std::size_t>(text);
  }
  expect_refused<long>("9223372036854775808");
  expect_refused<float>("1e39");  // beyond float, though a double
  EXPECT_EQ(parse_number<std::size_t>("--opt", "18446744073709551615"), UINT64_MAX);
  EXPECT_EQ(parse_number<int>("--opt", "-2147483648"), INT32_MIN);
}

TEST(ParseNumber, AcceptsDecimalNumbersWithSpacesAndOnePlus) {
  EXPECT_EQ(parse_number<float>("--opt", " 1.5 "), 1.5F);
  EXPECT_EQ(parse_number<double>("--opt", "+2e-3"), 2e-3);
  EXPECT_EQ(parse_number<double>("--opt", "-0.25"), -0.25);
  EXPECT_EQ(parse_number<unsigned>("--opt", "+7"), 7U);
  EXPECT_EQ(parse_number<int>("--opt", "-7\r"), -7);
}

TEST(ParseNumber, LimitsAndTheirMessages) {
  const NumberLimits positive{.min = 0, .min_exclusive = true};
  expect_refused<float>("0", positive);
  expect_refused<float>("-0", positive);
  EXPECT_EQ(parse_number<float>("--opt", "1e-30", positive), 1e-30F);
  const NumberLimits threads{.min = 0, .max = 4096};
  expect_refused<unsigned>("4097", threads);
  EXPECT_EQ(parse_number<unsigned>("--opt", "4096", threads), 4096U);
  try {
    (void)parse_number<unsigned>("--threads", "10000", threads);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), "--threads");
    EXPECT_STREQ(e.what(), "expected an integer in [0, 4096], got '10000'");
  }
  try {
    (void)parse_number<std::size_t>("--dim", "0", {.min = 1, .max = 1 << 20});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "expected an integer in [1, 1048576], got '0'") << "the bounds exactly";
  }
  try {
    (void)parse_number<float>("--gap", "nan", {.min = 0});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "expected a finite number >= 0, got 'nan'");
  }
}

}  // namespace
}  // namespace seqtopo
