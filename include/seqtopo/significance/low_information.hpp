#pragma once
// Frames whose appearance carries little evidence of place, found as a sequence search finds low-complexity
// sequence before it scores anything (SEG: the Shannon entropy of a window's composition, Wootton & Federhen
// 1993; DUST for DNA, Morgulis et al. 2006).
//
// Why: a near-black tunnel frame, a frame of fog or a bare wall resembles every other such frame, so a run of
// them matches another run as strongly as a revisit does (a Nordland season with a run of tunnels: a false loop
// closure of 60 pairs at E below 1e-9). The E-value cannot see it: it asks how often *chance* scores that well,
// and dark frames matching dark frames is not chance. A frame's composition tells it: the entropy of its grey
// levels, in bits, is below 1.5 in a tunnel of Nordland and 5.4 or more in 95 % of its daylight frames, 6 or more
// in every frame of the bundled corridor. The map takes such frames out of the evidence
// (mapping::MapConfig::mask_low_information).
//
// A frame is of little information when its entropy is below both `max_entropy` (an 8-bit image using fewer
// than about 2^4.5 = 23 grey levels evenly) and the sequence's median less `below_median` bits, so a camera whose
// every frame is dim (an infrared camera, a dark warehouse) keeps its frames: only those far below its own
// typical frame are masked.
#include <cstddef>
#include <span>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/core/running_median.hpp"

namespace seqtopo::significance {

// Shannon entropy [bits] of the image's grey levels (ITU-R BT.601 luma, 256 levels). 0 for an empty image.
double grey_entropy(const RgbImage& image);

struct LowInformationConfig {
  double max_entropy = 4.5;   // [bits]
  double below_median = 1.5;  // [bits]
};

// The frames (sorted indices) whose entropy is below both bounds. Throws std::invalid_argument for a bound
// that is negative or not finite.
std::vector<std::size_t> low_information_frames(std::span<const double> entropy,
                                                const LowInformationConfig& config = {});

// The listed frames of a sequence of n frames as n flags. Throws std::invalid_argument "`what` F is past the
// sequence's n frames" for a frame F >= n.
std::vector<bool> frame_flags(std::span<const std::size_t> frames, std::size_t n,
                              const char* what = "low-information frame");

// The same rule as the frames arrive (online mapping): a frame is of little information when its entropy is below
// max_entropy and the median of the entropies so far (its own included) less below_median. The median so far
// stands in for the whole sequence's, so the first frames of a dim camera may be judged before its typical frame
// is known; from a few dozen frames on the two rules agree but for frames near the bound.
class LowInformationStream {
 public:
  explicit LowInformationStream(const LowInformationConfig& config = {});  // throws as low_information_frames
  bool add(double entropy);

 private:
  LowInformationConfig config_;
  RunningMedian entropies_;  // so far
};

}  // namespace seqtopo::significance
