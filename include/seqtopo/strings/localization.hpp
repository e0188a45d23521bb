#pragma once
// String-matching localization (González-Buesa & Campos): every query string (a test point's fingerprint)
// is compared with every database string (the map points' fingerprints) by algorithm A, B or C; the
// candidates are ranked by score with ties kept, and the set of best matchings is scored against the
// ground truth as in the paper.
//
// Scores are costs (lower is better):
//   A: the weighted global alignment cost (banded_global_alignment); a pair with more than k
//      differences is no candidate.
//   B: the fewest differences of an occurrence of the query in the database string (k_differences);
//      no occurrence with <= k differences: no candidate.
//   C: the indel distance n + m - 2 * LCS (lcs_by_lis), which is why C is sensitive to length differences.
// With `cyclic`, each database string is read as a circular string and the best rotation is used.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/strings/banded_global_alignment.hpp"
#include "seqtopo/strings/costs.hpp"

namespace seqtopo::strings {

enum class Algorithm { A, B, C };
Algorithm parse_algorithm(std::string_view name);  // "A", "B" or "C"; throws std::invalid_argument
const char* algorithm_name(Algorithm algorithm);

struct MatchConfig {
  Algorithm algorithm = Algorithm::A;
  std::size_t k = kNoLimit;  // maximum differences (A, B); ignored by C
  EditCosts costs{};         // A only; B and C count unit differences
  bool cyclic = false;
  double tie_tolerance = 1e-9;  // scores closer than this are a tie (sums of decimal costs round)
};

struct PairScore {
  bool matched = false;  // false: more than k differences / no occurrence
  double score = 0.0;
  std::size_t rotation = 0;  // cyclic: the best rotation of the database string
};
PairScore score_pair(std::string_view query, std::string_view db, const MatchConfig& config);

struct Candidate {
  std::size_t db_index = 0;
  double score = 0.0;
  std::size_t rank = 1;  // 1 = among the best matchings; ties share a rank (1, 1, 3, ...)
  std::size_t rotation = 0;
};

struct QueryMatches {
  std::vector<Candidate> ranked;          // matched database strings, best first (ties by database order)
  std::vector<std::size_t> best() const;  // database indices of rank 1
};

std::vector<QueryMatches> match_all(const std::vector<std::string>& db, const std::vector<std::string>& queries,
                                    const MatchConfig& config);

// A sequence of consecutive fingerprints instead of one (beyond the paper). When test points and map
// points are each listed in travel order, test point q is localized with the `window` test points
// q - window + 1 .. q: the candidate map point d is scored by the cheapest monotone chain of map points
// d_0 <= d_1 <= ... <= d_last = d, each step advancing 0, 1 or 2 map points (test and map points need
// not be evenly spaced), as the mean of score(q - window + 1 + t, d_t). A chain through an unmatched pair
// is not allowed; no chain: no candidate. Fewer terms near the start of the list. window = 1 gives match_all.
std::vector<QueryMatches> match_all_windowed(const std::vector<std::string>& db,
                                             const std::vector<std::string>& queries, const MatchConfig& config,
                                             std::size_t window);

// ---- scoring (Section III) ----

struct Point2 {
  double x = 0.0, y = 0.0;  // [m]
};

struct GroundTruth {
  // adjacent[q][d]: map point d is adjacent to test point q (same place, or listed). Empty: unknown.
  std::vector<std::vector<bool>> adjacent;
  // Positions [m]; empty vectors: unknown. A missing entry leaves that point out of geometric scoring.
  std::vector<std::optional<Point2>> query_positions, db_positions;
};

struct Rates {
  std::size_t exact = 0, correct = 0, wrong = 0, total = 0;
  double percent(std::size_t count) const {
    return total == 0 ? 0.0 : 100.0 * static_cast<double>(count) / static_cast<double>(total);
  }
};

struct LocalizationMetrics {
  // A test point is topologically correct when its set of best matchings holds a map point adjacent to
  // it, and exact when that set is one single map point which is adjacent (Section III-A's definition,
  // which Tables I and V-VII need: read literally, III-B's "only one adjacent point in the set" would
  // make geometric exact equal geometric correct whenever the closest point is unique). Wrong = not correct.
  std::optional<Rates> topological;
  // Geometrically correct: the best set holds the map point closest to the test point (any of them on a
  // tie); exact: the best set is one single point and it is the closest. Counted over the topologically
  // correct test points only, as the paper does (over all test points when adjacency is unknown).
  std::optional<Rates> geometric;
};

LocalizationMetrics score_localization(const std::vector<QueryMatches>& matches, const GroundTruth& truth);

}  // namespace seqtopo::strings
