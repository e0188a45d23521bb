// libFuzzer harness: the FASTA reader. InputError is the documented rejection; an accepted file has at least one
// record and no empty sequence.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_input_file.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/fasta.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = seqtopo::fuzz::input_file(data, size);
  try {
    const auto records = seqtopo::io::read_fasta(path);
    if (records.empty()) std::abort();
    for (const auto& r : records) {
      if (r.sequence.empty()) std::abort();
    }
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
