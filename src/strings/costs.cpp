#include "seqtopo/strings/costs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace seqtopo::strings {

double EditCosts::min_diagonal_cost() const {
  double colour_min = 1.0;
  if (colour_distance) {
    for (int a = 0; a < kColourClasses; ++a) {
      for (int b = 0; b < kColourClasses; ++b) {
        if (a != b) colour_min = std::min(colour_min, (*colour_distance)[a][b]);
      }
    }
  }
  return std::min({coincidence, discordance, colour_difference * colour_min});
}

bool EditCosts::unit() const {
  return deletion == 1.0 && insertion == 1.0 && colour_difference == 1.0 && coincidence == 0.0 && discordance == 1.0 &&
         !colour_distance;
}

void validate(const EditCosts& c) {
  for (double v : {c.deletion, c.insertion, c.colour_difference, c.coincidence, c.discordance}) {
    if (!std::isfinite(v)) throw std::invalid_argument("edit costs must be finite numbers");
  }
  if (c.deletion < 0 || c.insertion < 0 || c.colour_difference < 0 || c.discordance < 0) {
    throw std::invalid_argument("deletion, insertion, colour difference and discordance costs must be >= 0");
  }
  if (c.colour_distance) {
    const auto& t = *c.colour_distance;
    for (int a = 0; a < kColourClasses; ++a) {
      if (t[a][a] != 0.0) throw std::invalid_argument("colour distance table: the diagonal must be 0");
      for (int b = 0; b < kColourClasses; ++b) {
        if (!(t[a][b] >= 0.0 && t[a][b] <= 1.0))
          throw std::invalid_argument("colour distance table: entries must be in [0, 1]");
        if (t[a][b] != t[b][a]) throw std::invalid_argument("colour distance table: must be symmetric");
      }
    }
  }
}

EditCosts preset_costs(std::string_view name) {
  // Order of the aggregate: deletion, insertion, colour difference, coincidence, discordance.
  if (name == "A1") return {1.0, 1.0, 1.0, 0.0, 1.0, {}};
  if (name == "A2-rooms") return {1.0, 1.0, 0.75, 0.0, 1.0, {}};
  if (name == "A2-ground-floor") return {0.55, 0.45, 0.7, -0.15, 3.0, {}};
  if (name == "A2-white-hall") return {0.7, 0.6, 1.0, 0.0, 1.5, {}};
  if (name == "A2-global") return {0.55, 0.45, 0.7, 0.0, 3.0, {}};
  throw std::invalid_argument("unknown cost preset '" + std::string(name) +
                              "' (A1, A2-rooms, A2-ground-floor, A2-white-hall, A2-global)");
}

std::vector<std::string> preset_names() { return {"A1", "A2-rooms", "A2-ground-floor", "A2-white-hall", "A2-global"}; }

}  // namespace seqtopo::strings
