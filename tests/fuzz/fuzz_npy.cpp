// libFuzzer harness: the .npy reader (header and matrix, float32 and float64). InputError is the documented
// rejection; anything else (another exception, a sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_input_file.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/npy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = seqtopo::fuzz::input_file(data, size);
  try {
    const auto header = seqtopo::io::read_npy_header(path);
    if (header.data_offset > size) std::abort();  // the header cannot end past the file
  } catch (const seqtopo::InputError&) {
  }
  try {
    const auto m = seqtopo::io::read_npy_matrix<float>(path);
    if (m.rows == 0 || m.cols == 0 || m.values.size() != m.rows * m.cols) std::abort();
  } catch (const seqtopo::InputError&) {
  }
  try {
    const auto m = seqtopo::io::read_npy_matrix<double>(path);
    if (m.values.size() != m.rows * m.cols) std::abort();
    // What is read is written back and read again to the same values.
    const auto encoded = seqtopo::io::encode_npy(m);
    const auto again = seqtopo::io::read_npy_matrix<double>(
        seqtopo::fuzz::input_file(reinterpret_cast<const std::uint8_t*>(encoded.data()), encoded.size()));
    if (again.rows != m.rows || again.cols != m.cols || again.values != m.values) std::abort();
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
