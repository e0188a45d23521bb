// formats::json_number: a float's shortest decimal as a double, which reads back as the same float.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "seqtopo/formats/json_number.hpp"

namespace seqtopo::formats {
namespace {

TEST(JsonNumber, ShortestDecimalThatReadsBackAsTheSameFloat) {
  EXPECT_EQ(json_number(0.85F), 0.85);
  EXPECT_EQ(json_number(0.5F), 0.5);
  EXPECT_EQ(json_number(-3.0F), -3.0);
  EXPECT_NE(static_cast<double>(0.85F), 0.85);  // what a JSON library would print without it
  std::mt19937 random(3);
  std::uniform_real_distribution<float> uniform(-1e6F, 1e6F);
  for (int k = 0; k < 10000; ++k) {
    const float v = uniform(random) * std::pow(10.0F, static_cast<float>(k % 13 - 6));
    EXPECT_EQ(static_cast<float>(json_number(v)), v) << v;
  }
  EXPECT_TRUE(std::isnan(json_number(std::numeric_limits<float>::quiet_NaN())));
}

}  // namespace
}  // namespace seqtopo::formats
