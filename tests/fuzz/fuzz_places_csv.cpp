// libFuzzer harness: places.csv and junctions.csv. InputError is the documented rejection.
#include <cstddef>
#include <cstdint>

#include "fuzz_input_file.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/places_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = seqtopo::fuzz::input_file(data, size);
  try {
    (void)seqtopo::formats::read_places_csv(path);
  } catch (const seqtopo::InputError&) {
  }
  try {
    (void)seqtopo::formats::read_junctions_csv(path);
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
