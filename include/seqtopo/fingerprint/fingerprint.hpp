#pragma once
// Panorama -> fingerprint string, after Lamon et al. ("Deriving and matching image fingerprint sequences
// for mobile robot localization", ICRA 2001; Fig. 1 of the string-matching localization paper).
//
// The panorama is cylindrical: 360 degrees across the width, column 0 at the robot's heading. Only a
// horizontal band of rows is read (band_top..band_bottom of the height) so floor and ceiling do not count.
// The string lists, in angular order (increasing column), two kinds of feature:
//
//   'v'       a vertical edge: a column where at least edge_min_fraction of the band rows have a
//             horizontal step max over R, G, B of |I(x+1) - I(x-1)| >= edge_step [levels], and which has the
//             most such rows among its +-edge_suppression neighbours (non-maximum suppression; the first
//             column wins a tie). Neighbours wrap around the image edge.
//   'A'..'P'  a colour patch: a run of at least min_patch_width consecutive columns [pixels = degrees for
//             a 360-pixel panorama] whose dominant colour class is the same. A column's dominant class is
//             the class of at least column_majority of its band pixels (otherwise the column has none).
//             A run that crosses column 0 is one patch, listed at its first column.
// At the same column an edge comes before a patch.
//
// Before classification the band's brightness (max of R, G, B) is scaled so that its brightness_percentile
// reaches brightness_target (0 = off): a test point photographed under another exposure keeps its classes.
// Colour classes (hue / saturation / brightness of the pixel, HSV with S, V in [0, 1]):
//   achromatic (S < saturation_min or V < value_min_colour), by brightness V:
//     'A' black V < 0.25, 'B' dark grey V < 0.5, 'C' light grey V < 0.75, 'D' white;
//   chromatic, by hue sector of 60 degrees centred on red 0, yellow 60, green 120, cyan 180, blue 240,
//   magenta 300, and by brightness (dark: V < bright_value):
//     dark  'E' red, 'F' yellow, 'G' green, 'H' cyan, 'I' blue, 'J' magenta;
//     bright 'K' red, 'L' yellow, 'M' green, 'N' cyan, 'O' blue, 'P' magenta.
// colour_class_distances() places each class at a representative colour in the HSV cone
// (x, y, z) = (S V cos H, S V sin H, V) and gives their Euclidean distances divided by the largest one,
// so a colour difference between neighbouring classes costs less than between opposite ones.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "seqtopo/core/rgb_image.hpp"
#include "seqtopo/strings/costs.hpp"

namespace seqtopo::fingerprint {

struct FingerprintConfig {
  double band_top = 0.2;           // fraction of the height where the scanned band starts
  double band_bottom = 0.8;        // ... and ends
  double edge_step = 24.0;         // [levels of the most changing channel] between a pixel's two neighbours
  double edge_min_fraction = 0.6;  // of band rows with such a step
  int edge_suppression = 2;        // [columns] each side
  double saturation_min = 0.25;
  double value_min_colour = 0.15;
  double bright_value = 0.6;
  double column_majority = 0.5;
  int min_patch_width = 6;             // [columns]
  double brightness_percentile = 0.9;  // 0 = no brightness normalization
  double brightness_target = 0.9;      // fraction of full scale
};

struct Feature {
  int column = 0;  // [pixels] from the heading, counter-clockwise
  char symbol = 'v';
};

struct Fingerprint {
  std::string symbols;            // the string, e.g. "vAvKvvD"
  std::vector<Feature> features;  // the same features with their columns
};

// Throws std::invalid_argument for an empty image or an invalid configuration.
Fingerprint extract_fingerprint(const RgbImage& panorama, const FingerprintConfig& config = {});

// Colour class (0..15 for 'A'..'P') of one pixel.
int colour_class(std::uint8_t r, std::uint8_t g, std::uint8_t b, const FingerprintConfig& config = {});

// Pairwise distances in [0, 1] between the 16 classes, for EditCosts::colour_distance.
strings::ColourDistanceTable colour_class_distances();

// A representative RGB colour of a class (for pictures and synthetic tests).
std::array<std::uint8_t, 3> class_colour(int colour_class);

}  // namespace seqtopo::fingerprint
