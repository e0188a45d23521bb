#pragma once
// A heading-invariant descriptor of a 360-degree panorama (localization paper's omnidirectional camera;
// `seqtopo simulate` writes such images).
//
// Why: a panorama taken at the same spot facing another way is the same image shifted circularly along its
// width. A path revisited in the opposite direction (the mapping paper's experiment 1) is then invisible to
// thumbnails compared pixel by pixel, and a lighting change between traversals hurts colour histograms.
// Here the panorama is reduced to `bands` horizontal bands of `columns` samples (area averaging), each
// band and channel (luma and two colour opponents) is normalised to mean 0 and standard deviation 1 around
// the circle (removing the gain and tint of the lighting), and only the magnitudes of its discrete Fourier
// transform along the circle are kept, harmonics 1..harmonics: a circular shift changes only the phases.
// Compare signatures with Distance::l1 or sad.
#include <vector>

#include "seqtopo/core/rgb_image.hpp"

namespace seqtopo::image {

struct PanoramaConfig {
  int columns = 64;    // samples around the circle
  int bands = 8;       // horizontal bands, top to bottom
  int harmonics = 16;  // Fourier magnitudes kept per band and channel (1..harmonics; <= columns / 2)
  bool colour = true;  // also the two colour-opponent channels (R - G, (R + G) / 2 - B)

  int channels() const { return colour ? 3 : 1; }
  std::size_t dimension() const {
    return static_cast<std::size_t>(bands) * static_cast<std::size_t>(channels()) * static_cast<std::size_t>(harmonics);
  }
};

// dimension() values: band-major, then channel, then harmonic. A flat band gives zeros. Throws
// std::invalid_argument on an empty image or an unusable config.
std::vector<float> panorama_signature(const RgbImage& image, const PanoramaConfig& config = {});

}  // namespace seqtopo::image
