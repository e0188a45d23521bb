#include "seqtopo/strings/localization.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "seqtopo/strings/cyclic.hpp"
#include "seqtopo/strings/k_differences.hpp"
#include "seqtopo/strings/lcs_by_lis.hpp"

namespace seqtopo::strings {

Algorithm parse_algorithm(std::string_view name) {
  if (name == "A") return Algorithm::A;
  if (name == "B") return Algorithm::B;
  if (name == "C") return Algorithm::C;
  throw std::invalid_argument("unknown algorithm '" + std::string(name) + "' (A, B or C)");
}

const char* algorithm_name(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::A:
      return "A";
    case Algorithm::B:
      return "B";
    case Algorithm::C:
      return "C";
  }
  return "?";
}

PairScore score_pair(std::string_view query, std::string_view db, const MatchConfig& config) {
  PairScore out;
  switch (config.algorithm) {
    case Algorithm::A: {
      const GlobalAlignmentConfig c{config.k, config.costs, false};
      GlobalAlignment a;
      if (config.cyclic) {
        const auto cyc = cyclic_banded_global_alignment(query, db, c);
        a = cyc.alignment;
        out.rotation = cyc.rotation;
      } else {
        a = banded_global_alignment(query, db, c);
      }
      out.matched = a.within_k;
      out.score = a.cost;
      break;
    }
    case Algorithm::B: {
      const KDifferencesConfig c{config.k};
      std::optional<std::size_t> best;
      if (config.cyclic) {
        const auto cyc = cyclic_k_differences(query, db, c);
        best = cyc.best_differences();
        out.rotation = cyc.rotation;
      } else {
        best = k_differences(query, db, c).best_differences();
      }
      out.matched = best.has_value();
      out.score = best ? static_cast<double>(*best) : 0.0;
      break;
    }
    case Algorithm::C: {
      std::size_t length = 0;
      if (config.cyclic) {
        const auto cyc = cyclic_lcs_by_lis(query, db);
        length = cyc.lcs.length;
        out.rotation = cyc.rotation;
      } else {
        length = lcs_by_lis(query, db).length;
      }
      out.matched = true;
      out.score = static_cast<double>(query.size() + db.size() - 2 * length);
      break;
    }
  }
  return out;
}

std::vector<std::size_t> QueryMatches::best() const {
  std::vector<std::size_t> out;
  for (const Candidate& c : ranked) {
    if (c.rank == 1) out.push_back(c.db_index);
  }
  return out;
}

namespace {

QueryMatches rank(std::vector<Candidate> candidates, double tolerance) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  // A tie group starts at its best score; everything within the tolerance of it shares the rank.
  double group_score = 0.0;
  std::size_t group_rank = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (i == 0 || candidates[i].score - group_score > tolerance) {
      group_score = candidates[i].score;
      group_rank = i + 1;
    }
    candidates[i].rank = group_rank;
  }
  return {std::move(candidates)};
}

}  // namespace

std::vector<QueryMatches> match_all(const std::vector<std::string>& db, const std::vector<std::string>& queries,
                                    const MatchConfig& config) {
  return match_all_windowed(db, queries, config, 1);
}

std::vector<QueryMatches> match_all_windowed(const std::vector<std::string>& db,
                                             const std::vector<std::string>& queries, const MatchConfig& config,
                                             std::size_t window) {
  if (window == 0) throw std::invalid_argument("match window must be >= 1");
  if (config.algorithm == Algorithm::A) validate(config.costs);
  if (!(config.tie_tolerance >= 0.0)) throw std::invalid_argument("tie tolerance must be >= 0");
  std::vector<std::vector<PairScore>> scores(queries.size(), std::vector<PairScore>(db.size()));
  for (std::size_t q = 0; q < queries.size(); ++q) {
    for (std::size_t d = 0; d < db.size(); ++d) scores[q][d] = score_pair(queries[q], db[d], config);
  }
  const double inf = std::numeric_limits<double>::infinity();
  auto cost = [&](std::size_t q, std::size_t d) { return scores[q][d].matched ? scores[q][d].score : inf; };
  std::vector<QueryMatches> out;
  out.reserve(queries.size());
  std::vector<double> chain(db.size()), next(db.size());
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const std::size_t first = q + 1 >= window ? q + 1 - window : 0;
    for (std::size_t d = 0; d < db.size(); ++d) chain[d] = cost(first, d);
    for (std::size_t t = first + 1; t <= q; ++t) {
      for (std::size_t d = 0; d < db.size(); ++d) {
        double from = chain[d];
        if (d >= 1) from = std::min(from, chain[d - 1]);
        if (d >= 2) from = std::min(from, chain[d - 2]);
        next[d] = from + cost(t, d);
      }
      chain.swap(next);
    }
    const auto terms = static_cast<double>(q - first + 1);
    std::vector<Candidate> candidates;
    for (std::size_t d = 0; d < db.size(); ++d) {
      if (chain[d] == inf) continue;
      candidates.push_back({d, terms == 1 ? chain[d] : chain[d] / terms, 1, scores[q][d].rotation});
    }
    out.push_back(rank(std::move(candidates), config.tie_tolerance));
  }
  return out;
}

LocalizationMetrics score_localization(const std::vector<QueryMatches>& matches, const GroundTruth& truth) {
  const std::size_t nq = matches.size();
  LocalizationMetrics metrics;
  const bool have_adjacency = !truth.adjacent.empty();
  if (have_adjacency && truth.adjacent.size() != nq) throw std::invalid_argument("adjacency: one row per query needed");
  const bool have_positions = !truth.query_positions.empty() && !truth.db_positions.empty();
  if (have_positions && truth.query_positions.size() != nq)
    throw std::invalid_argument("positions: one per query needed");

  std::vector<bool> topologically_correct(nq, true);
  if (have_adjacency) {
    Rates r;
    for (std::size_t q = 0; q < nq; ++q) {
      const auto best = matches[q].best();
      const auto& adj = truth.adjacent[q];
      auto adjacent = [&](std::size_t d) {
        if (d >= adj.size()) throw std::invalid_argument("adjacency: row shorter than the database");
        return static_cast<bool>(adj[d]);
      };
      const bool correct = std::any_of(best.begin(), best.end(), adjacent);
      const bool exact = best.size() == 1 && correct;
      ++r.total;
      r.correct += correct ? 1 : 0;
      r.exact += exact ? 1 : 0;
      r.wrong += correct ? 0 : 1;
      topologically_correct[q] = correct;
    }
    metrics.topological = r;
  }
  if (have_positions) {
    Rates r;
    for (std::size_t q = 0; q < nq; ++q) {
      if (!topologically_correct[q] || !truth.query_positions[q]) continue;
      const Point2 p = *truth.query_positions[q];
      double nearest = std::numeric_limits<double>::infinity();
      std::vector<double> dist(truth.db_positions.size(), std::numeric_limits<double>::infinity());
      for (std::size_t d = 0; d < truth.db_positions.size(); ++d) {
        if (!truth.db_positions[d]) continue;
        dist[d] = std::hypot(truth.db_positions[d]->x - p.x, truth.db_positions[d]->y - p.y);
        nearest = std::min(nearest, dist[d]);
      }
      if (nearest == std::numeric_limits<double>::infinity()) continue;
      auto closest = [&](std::size_t d) { return d < dist.size() && dist[d] <= nearest + 1e-9; };
      const auto best = matches[q].best();
      const bool correct = std::any_of(best.begin(), best.end(), closest);
      const bool exact = best.size() == 1 && correct;
      ++r.total;
      r.correct += correct ? 1 : 0;
      r.exact += exact ? 1 : 0;
      r.wrong += correct ? 0 : 1;
    }
    metrics.geometric = r;
  }
  return metrics;
}

}  // namespace seqtopo::strings
