#include "seqtopo/evaluation/loop_closure_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

namespace seqtopo::evaluation {

PrSweep sweep_precision_recall(const std::vector<float>& scores, const std::vector<bool>& correct,
                               std::size_t positives) {
  if (scores.size() != correct.size()) throw std::invalid_argument("one correctness flag per score needed");
  std::vector<std::size_t> order(scores.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  PrSweep sweep;
  std::size_t tp = 0, fp = 0;
  double previous_recall = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    (correct[order[k]] ? tp : fp) += 1;
    if (k + 1 < order.size() && scores[order[k + 1]] == scores[order[k]]) continue;  // not the last of this score
    PrPoint point{scores[order[k]], static_cast<double>(tp) / static_cast<double>(tp + fp),
                  positives == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(positives)};
    sweep.auc += (point.recall - previous_recall) * point.precision;
    previous_recall = point.recall;
    if (fp == 0) sweep.recall_at_100_precision = point.recall;
    sweep.curve.push_back(point);
  }
  return sweep;
}

std::vector<ScoredPair> best_pair_per_image(const std::vector<ScoredPair>& pairs) {
  std::map<std::size_t, ScoredPair> best;
  for (const auto& p : pairs) {
    if (p.j >= p.i) continue;
    auto it = best.find(p.i);
    if (it == best.end() || p.score > it->second.score || (p.score == it->second.score && p.j > it->second.j)) {
      best[p.i] = p;
    }
  }
  std::vector<ScoredPair> out;
  out.reserve(best.size());
  for (const auto& [i, p] : best) out.push_back(p);
  return out;
}

std::vector<bool> images_with_earlier_partner(std::size_t images, const SamePlace& same_place,
                                              std::size_t min_separation) {
  std::vector<bool> has_partner(images, false);
  for (std::size_t i = 0; i < images; ++i) {
    for (std::size_t j = 0; j + min_separation <= i; ++j) {
      if (same_place(i, j)) {
        has_partner[i] = true;
        break;
      }
    }
  }
  return has_partner;
}

std::vector<bool> images_with_earlier_partner(std::span<const Pose2> positions, double radius,
                                              std::size_t min_separation) {
  if (!(radius > 0)) throw std::invalid_argument("same-place radius must be > 0");
  // Cells a little wider than the radius (so that rounding cannot move a partner two cells away): a partner within
  // the radius is in the image's cell or one of its eight neighbours.
  const double width = radius * (1 + 1e-6);
  const auto cell_of = [width](const Pose2& p) {
    return std::pair{static_cast<std::int64_t>(std::floor(p.x / width)),
                     static_cast<std::int64_t>(std::floor(p.y / width))};
  };
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::size_t>> cells;  // images by increasing index
  for (std::size_t i = 0; i < positions.size(); ++i) cells[cell_of(positions[i])].push_back(i);
  const double r2 = radius * radius;
  std::vector<bool> has_partner(positions.size(), false);
  for (std::size_t i = min_separation; i < positions.size(); ++i) {
    const auto [cx, cy] = cell_of(positions[i]);
    for (std::int64_t dx = -1; dx <= 1 && !has_partner[i]; ++dx) {
      for (std::int64_t dy = -1; dy <= 1 && !has_partner[i]; ++dy) {
        const auto it = cells.find({cx + dx, cy + dy});
        if (it == cells.end()) continue;
        for (const std::size_t j : it->second) {
          if (j + min_separation > i) break;
          const double ex = positions[i].x - positions[j].x, ey = positions[i].y - positions[j].y;
          if (ex * ex + ey * ey <= r2) {
            has_partner[i] = true;
            break;
          }
        }
      }
    }
  }
  return has_partner;
}

std::vector<bool> images_with_earlier_partner(std::size_t images, const SamePlace& same_place,
                                              const EarlierPartners& finder, std::size_t min_separation) {
  if (!finder) return images_with_earlier_partner(images, same_place, min_separation);
  auto has_partner = finder(min_separation);
  if (has_partner.size() != images) throw std::invalid_argument("earlier partners: one per image expected");
  return has_partner;
}

LoopClosureMetrics evaluate_loop_closures(const std::vector<ScoredPair>& pairs, std::size_t images,
                                          const SamePlace& same_place, std::size_t min_separation) {
  return evaluate_loop_closures(pairs, images_with_earlier_partner(images, same_place, min_separation), same_place);
}

LoopClosureMetrics evaluate_loop_closures(const std::vector<ScoredPair>& pairs, const std::vector<bool>& has_partner,
                                          const SamePlace& same_place) {
  const std::size_t images = has_partner.size();
  for (const auto& p : pairs) {
    if (p.i >= images || p.j >= images) {
      throw std::invalid_argument("pair (" + std::to_string(p.i) + ", " + std::to_string(p.j) + ") outside " +
                                  std::to_string(images) + " images");
    }
  }
  LoopClosureMetrics m;
  for (std::size_t i = 0; i < images; ++i) m.images_with_partner += has_partner[i] ? 1 : 0;

  auto detections = best_pair_per_image(pairs);
  std::vector<bool> correct(detections.size());
  for (std::size_t k = 0; k < detections.size(); ++k) correct[k] = same_place(detections[k].i, detections[k].j);

  auto finish = [&](std::size_t tp, std::size_t fp, double& precision, double& recall) {
    precision = tp + fp == 0 ? 1.0 : static_cast<double>(tp) / static_cast<double>(tp + fp);
    recall = m.images_with_partner == 0 ? 0.0 : static_cast<double>(tp) / static_cast<double>(m.images_with_partner);
  };
  for (std::size_t k = 0; k < detections.size(); ++k) (correct[k] ? m.tp : m.fp) += 1;
  m.fn = m.images_with_partner - m.tp;  // every true positive is an image with a partner
  finish(m.tp, m.fp, m.precision, m.recall);
  m.f1 = m.precision + m.recall == 0 ? 0.0 : 2 * m.precision * m.recall / (m.precision + m.recall);

  std::vector<float> scores;
  for (const auto& d : detections) scores.push_back(d.score);
  auto sweep = sweep_precision_recall(scores, correct, m.images_with_partner);
  m.curve = std::move(sweep.curve);
  m.auc = sweep.auc;
  m.recall_at_100_precision = sweep.recall_at_100_precision;
  return m;
}

LoopClosureErrors loop_closure_errors(const std::vector<ScoredPair>& pairs, const std::vector<bool>& has_partner,
                                      const SamePlace& same_place, std::size_t min_separation,
                                      std::size_t max_partners) {
  LoopClosureErrors e;
  std::vector<bool> true_positive(has_partner.size(), false);
  for (const auto& d : best_pair_per_image(pairs)) {
    if (same_place(d.i, d.j)) {
      if (d.i < true_positive.size()) true_positive[d.i] = true;
    } else {
      e.false_positives.push_back(d);
    }
  }
  for (std::size_t i = 0; i < has_partner.size(); ++i) {
    if (!has_partner[i] || true_positive[i]) continue;
    MissedRevisit m{i, i};
    if (e.missed.size() < max_partners) {
      for (std::size_t j = i - std::min(i, min_separation) + 1; j-- > 0;) {
        if (i - j >= min_separation && same_place(i, j)) {
          m.partner = j;
          break;
        }
      }
    }
    e.missed.push_back(m);
  }
  return e;
}

}  // namespace seqtopo::evaluation
