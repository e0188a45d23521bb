// libFuzzer harness: odometry and ground-truth pose CSV files. InputError is the documented rejection; an
// accepted file has finite poses only.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "fuzz_input_file.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/odometry_csv.hpp"

namespace {

void check_finite(const std::vector<seqtopo::Pose2>& poses) {
  for (const auto& p : poses) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = seqtopo::fuzz::input_file(data, size);
  try {
    check_finite(seqtopo::formats::read_odometry_csv(path));
  } catch (const seqtopo::InputError&) {
  }
  try {
    check_finite(seqtopo::formats::read_poses_csv(path));
  } catch (const seqtopo::InputError&) {
  }
  return 0;
}
