// libFuzzer harness: strings files (`seqtopo match-strings`). StringsFileError (a std::invalid_argument) is the
// documented rejection; an accepted file formats to text that parses again to as many records with the same ids
// and symbols, the same coordinates to the bit and the same places.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "seqtopo/strings/strings_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace seqtopo::strings;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)parse_strings_tsv(text);
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
      if (again[k].x != records[k].x || again[k].y != records[k].y || again[k].place != records[k].place) std::abort();
    }
  } catch (const StringsFileError&) {
    std::abort();
  }
  return 0;
}
