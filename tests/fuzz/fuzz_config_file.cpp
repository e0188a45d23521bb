// libFuzzer harness: the `--config FILE` parser. InputError is the documented rejection; every entry has a
// name and a line inside the text.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "config_file.hpp"
#include "seqtopo/core/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    for (const auto& e : seqtopo::cli::parse_config(text, "fuzz.yaml")) {
      if (e.name.empty() || e.line == 0 || e.line > size) std::abort();
    }
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
