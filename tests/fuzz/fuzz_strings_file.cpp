// libFuzzer harness: strings files (`seqtopo match-strings`). StringsFileError (a std::invalid_argument) is the
// documented rejection; an accepted file formats to text that parses again to as many records with the same ids
// and symbols. Not checked: coordinates within 1e-9 of the largest double, which format_strings_tsv's 10
// significant digits round up past it (1.7976931348623157e308 is written as 1.797693135e+308, not a number),
// and places ending in '\r' (`p\r\r\n` is the place `p\r`; written back, its '\r' is read as the line end).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "seqtopo/strings/strings_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace seqtopo::strings;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto records = parse_strings_tsv(text);
    for (const auto& r : records) {
      if (r.x && (std::abs(*r.x) > 1.797693134e308 || std::abs(*r.y) > 1.797693134e308)) return 0;
      if (r.place && r.place->back() == '\r') return 0;
    }
  } catch (const StringsFileError&) {
    return 0;
  }
  // Accepted: the formatted records must be accepted too.
  try {
    const auto records = parse_strings_tsv(text);
    const auto again = parse_strings_tsv(format_strings_tsv(records));
    if (again.size() != records.size()) std::abort();
    for (std::size_t k = 0; k < records.size(); ++k) {
      if (again[k].id != records[k].id || again[k].symbols != records[k].symbols) std::abort();
    }
  } catch (const StringsFileError&) {
    std::abort();
  }
  return 0;
}
