#include "seqtopo/evaluation/localization_metrics.hpp"

#include <algorithm>
#include <charconv>
#include <numeric>
#include <stdexcept>
#include <string>

namespace seqtopo::evaluation {

LocalizationTruth LocalizationTruth::same_index(std::size_t query_frames, std::size_t map_frames) {
  LocalizationTruth t;
  t.map_frames = map_frames;
  t.truth.resize(query_frames);
  for (std::size_t q = 0; q < query_frames && q < map_frames; ++q) t.truth[q] = {q};
  return t;
}

LocalizationTruth LocalizationTruth::from_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                                std::size_t query_frames, std::size_t map_frames) {
  LocalizationTruth t;
  t.map_frames = map_frames;
  t.truth.resize(query_frames);
  for (const auto& [q, m] : pairs) {
    if (q >= query_frames || m >= map_frames) {
      throw std::invalid_argument("ground-truth pair (" + std::to_string(q) + ", " + std::to_string(m) + ") outside " +
                                  std::to_string(query_frames) + " query x " + std::to_string(map_frames) +
                                  " map frames");
    }
    t.truth[q].push_back(m);
  }
  for (auto& v : t.truth) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  return t;
}

bool LocalizationTruth::correct(std::size_t query, std::size_t map, std::size_t tolerance) const {
  if (query >= truth.size()) return false;
  const auto& v = truth[query];
  // The first true frame >= map - tolerance decides.
  const std::size_t lo = map >= tolerance ? map - tolerance : 0;
  const auto it = std::lower_bound(v.begin(), v.end(), lo);
  return it != v.end() && *it <= map + tolerance;
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool parse_index(std::string_view s, std::size_t& out) {
  s = trim(s);
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> parse_pairs_csv(std::string_view text) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::size_t line_number = 0;
  bool first_content = true;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = trim(text.substr(0, end));
    text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
    ++line_number;
    if (line.empty()) continue;
    const std::size_t comma = line.find(',');
    std::size_t q = 0, m = 0;
    const bool ok = comma != std::string_view::npos && parse_index(line.substr(0, comma), q) &&
                    parse_index(line.substr(comma + 1), m);
    if (!ok) {
      if (first_content && trim(line.substr(0, comma)) == "query" && comma != std::string_view::npos &&
          trim(line.substr(comma + 1)) == "map") {
        first_content = false;
        continue;
      }
      throw std::invalid_argument("line " + std::to_string(line_number) +
                                  ": expected 'query,map' with two non-negative integer frame indices");
    }
    first_content = false;
    pairs.emplace_back(q, m);
  }
  return pairs;
}

LocalizationMetrics evaluate_localization(const std::vector<LocalizationPrediction>& predictions,
                                          const LocalizationTruth& truth, std::size_t tolerance) {
  if (predictions.size() != truth.truth.size()) {
    throw std::invalid_argument("there are " + std::to_string(predictions.size()) + " predictions for " +
                                std::to_string(truth.truth.size()) + " query frames");
  }
  LocalizationMetrics m;
  m.queries = predictions.size();
  std::vector<char> correct(predictions.size(), 0);
  std::size_t hits1 = 0, hits5 = 0;
  for (std::size_t q = 0; q < predictions.size(); ++q) {
    const auto& p = predictions[q];
    const bool has_match = !truth.truth[q].empty();
    m.queries_with_match += has_match ? 1 : 0;
    if (!p.map) continue;
    if (truth.map_frames != 0 && *p.map >= truth.map_frames) {
      throw std::invalid_argument("prediction " + std::to_string(*p.map) + " of query frame " + std::to_string(q) +
                                  " outside the " + std::to_string(truth.map_frames) + " map frames");
    }
    ++m.predicted;
    correct[q] = truth.correct(q, *p.map, tolerance) ? 1 : 0;
    m.correct += correct[q];
    if (!has_match) continue;
    hits1 += correct[q];
    // recall@5 looks at the map frame first, then the candidates after it.
    bool any = correct[q] != 0;
    for (std::size_t k = 0; k < p.candidates.size() && k < 5 && !any; ++k)
      any = truth.correct(q, p.candidates[k], tolerance);
    hits5 += any ? 1 : 0;
  }
  const auto with_match = static_cast<double>(m.queries_with_match);
  auto ratio = [&](std::size_t n) { return m.queries_with_match == 0 ? 0.0 : static_cast<double>(n) / with_match; };
  m.recall_at_1 = ratio(hits1);
  m.recall_at_5 = ratio(hits5);
  m.precision = m.predicted == 0 ? 1.0 : static_cast<double>(m.correct) / static_cast<double>(m.predicted);
  m.recall = ratio(m.correct);

  std::vector<float> scores;
  std::vector<bool> accepted_correct;
  for (std::size_t q = 0; q < predictions.size(); ++q) {
    if (!predictions[q].map) continue;
    scores.push_back(predictions[q].score);
    accepted_correct.push_back(correct[q] != 0);
  }
  auto sweep = sweep_precision_recall(scores, accepted_correct, m.queries_with_match);
  m.curve = std::move(sweep.curve);
  m.auc = sweep.auc;
  m.recall_at_100_precision = sweep.recall_at_100_precision;
  return m;
}

}  // namespace seqtopo::evaluation
