#pragma once
// The edit costs of the string-matching localization paper (González-Buesa & Campos), Tables III and IV.
//
// Fingerprint strings have two kinds of symbol: 'v' (a vertical edge) and 'A'..'P' (one of 16 colour
// classes). Aligning pattern symbol p with text symbol t costs
//   coincidence                                   if p == t,
//   colour_difference * scale(p, t)               if p and t are two different colour classes,
//   discordance                                   otherwise (an edge against a colour, or any other
//                                                 pair of different symbols),
// where scale is 1 unless a colour distance table is given (then the table entry, in [0, 1]).
// Deleting a pattern symbol costs `deletion`, inserting a text symbol costs `insertion`.
// The unit costs (Table III, "A1") give the plain edit distance.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::strings {

inline constexpr int kColourClasses = 16;  // 'A'..'P'

// Colour class index of a symbol, or -1 when it is not a colour patch.
constexpr int colour_class(char symbol) { return symbol >= 'A' && symbol < 'A' + kColourClasses ? symbol - 'A' : -1; }

// distance[a][b] in [0, 1] between colour classes a and b (0 on the diagonal), scaling colour_difference.
using ColourDistanceTable = std::array<std::array<double, kColourClasses>, kColourClasses>;

struct EditCosts {
  double deletion = 1.0;           // delete a pattern symbol
  double insertion = 1.0;          // insert a text symbol
  double colour_difference = 1.0;  // two different colour classes
  double coincidence = 0.0;        // equal symbols (may be negative: a reward)
  double discordance = 1.0;        // an edge against a colour patch, or any other mismatch
  std::optional<ColourDistanceTable> colour_distance;

  double substitution(char p, char t) const {
    if (p == t) return coincidence;
    const int a = colour_class(p), b = colour_class(t);
    if (a >= 0 && b >= 0) {
      return colour_distance ? colour_difference * (*colour_distance)[a][b] : colour_difference;
    }
    return discordance;
  }
  // The smallest cost a diagonal step can have (for lower bounds).
  double min_diagonal_cost() const;
  // True for the plain edit distance: every difference costs 1, a coincidence 0.
  bool unit() const;
};

// Throws std::invalid_argument unless every cost is finite, deletion/insertion/colour_difference/
// discordance are >= 0 and the colour table (if any) is symmetric, in [0, 1], with a zero diagonal.
void validate(const EditCosts& costs);

// Named cost tables of the paper: "A1" (Table III), "A2-rooms" (Section III-A: colour difference 0.75),
// "A2-ground-floor", "A2-white-hall", "A2-global" (the columns of Table IV).
EditCosts preset_costs(std::string_view name);  // throws std::invalid_argument for an unknown name
std::vector<std::string> preset_names();

}  // namespace seqtopo::strings
