// libFuzzer harness: the small CSV reader with an exact header. The first byte chooses the header, the rest is
// the file. InputError is the documented rejection.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_input_file.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::vector<std::string>> headers = {
      {"index", "place"}, {"place"}, {"a", "b", "c"}, {"i", "j", "score"}, {"x", "y"}};
  if (size == 0) return 0;
  const auto& header = headers[data[0] % headers.size()];
  const auto path = seqtopo::fuzz::input_file(data + 1, size - 1);
  try {
    for (const auto& row : seqtopo::io::read_csv(path, header)) {
      if (row.fields.size() != header.size() || row.where.empty()) std::abort();
    }
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
