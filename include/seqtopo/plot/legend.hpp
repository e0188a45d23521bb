#pragma once
// A legend entry of a figure: a mark in a colour and what it stands for.
#include <array>
#include <cstdint>
#include <string>

namespace seqtopo::plot {

struct LegendEntry {
  enum class Mark { line, dashed_line, dot, hollow_square };
  std::string label;
  std::array<std::uint8_t, 3> rgb{0, 0, 0};
  Mark mark = Mark::line;
};

}  // namespace seqtopo::plot
