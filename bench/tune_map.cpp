// Chooses the map defaults on real data: sweeps the alignment parameters over a similarity matrix and
// scores each setting against the ground truth, next to the SeqSLAM-style baseline on the same matrix.
//
//   [ENHANCE=W [FUSE=OTHER.npy]] [GAPS=..] [CAPS=..] [THRESHOLDS=..] [SEPARATIONS=..]
//   tune_map SIMILARITY.npy (GT_IMAGE | POSES.csv RADIUS) [multipliers, e.g. 0.5,1,2]
//
// Without ENHANCE a multiplier m rescales S = 1 - kappa D to 1 - m kappa D = 1 - m (1 - S) (more or
// fewer pairs rewarded) without recomputing descriptors; with ENHANCE it is the contrast offset.
// Lists (comma-separated) override the parameter grid. Prints the best settings by F1, AUC, R@100P.
// The defaults of mapping::MapConfig came from:
//   ENHANCE=10 FUSE=patch/similarity.npy tune_map joint-histogram/similarity.npy GT 0.5
// on the corridor (ground_truth.bmp) and on Nordland summer+winter (poses.csv 2).
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/pipeline/baselines.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"

using namespace seqtopo;

namespace {

struct Row {
  double f1, auc, r100, precision, recall;
  std::string setting;
};

std::vector<double> parse_list(const std::string& text) {
  std::vector<double> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: tune_map SIMILARITY.npy (GT_IMAGE | POSES.csv RADIUS) [kappa multipliers]\n";
    return 2;
  }
  const auto base = io::read_npy_matrix<float>(argv[1]);
  const std::size_t n = base.rows;
  int next = 2;
  const std::string gt = argv[next++];
  const std::optional<double> radius = gt.size() > 4 && gt.substr(gt.size() - 4) == ".csv"
                                           ? std::optional<double>(std::stod(argv[next++]))
                                           : std::nullopt;
  const evaluation::SamePlace same_place = pipeline::load_same_place(gt, radius, n).same_place;
  const auto multipliers = argc > next ? parse_list(argv[next]) : std::vector<double>{1.0};
  const auto gaps = std::getenv("GAPS") ? parse_list(std::getenv("GAPS")) : std::vector<double>{0.3, 1, 2};
  const auto caps = std::getenv("CAPS") ? parse_list(std::getenv("CAPS")) : std::vector<double>{2, 4, 8, 0};
  const auto thresholds =
      std::getenv("THRESHOLDS") ? parse_list(std::getenv("THRESHOLDS")) : std::vector<double>{1, 2, 3, 5, 8};
  const auto separations =
      std::getenv("SEPARATIONS") ? parse_list(std::getenv("SEPARATIONS")) : std::vector<double>{5, 15};

  std::vector<Row> rows, baseline_rows;
  for (double mult : multipliers) {
    // ENHANCE=W: the default pipeline's scores (contrast window W, offset = the multiplier), fused with
    // FUSE=other.npy when given; otherwise the paper's raw S rescaled by the multiplier.
    SimilarityMatrix s = base;
    if (const char* window = std::getenv("ENHANCE")) {
      mapping::MapConfig c;
      c.score.contrast_window = static_cast<std::size_t>(std::atoi(window));
      c.score.contrast_offset = static_cast<float>(mult);
      std::vector<SimilarityMatrix> sources{base};
      if (const char* other = std::getenv("FUSE")) sources.push_back(io::read_npy_matrix<float>(other));
      s = mapping::alignment_scores(sources, c);
    } else {
      for (auto& v : s.values) v = static_cast<float>(1.0 - mult * (1.0 - v));
    }
    for (double sep : separations) {
      baseline::SeqSlamConfig sc;
      sc.self = true;
      sc.min_separation = static_cast<std::size_t>(sep);
      for (std::size_t len : {5, 10, 20}) {
        sc.sequence_length = len;
        // the baseline's operating point: the best F1 over its threshold sweep
        const auto all = evaluation::evaluate_loop_closures(pipeline::seqslam_loop_closures(s, sc), n, same_place,
                                                            sc.min_separation);
        const double best_f1 = pipeline::best_f1_threshold(all.curve).second;
        baseline_rows.push_back({best_f1, all.auc, all.recall_at_100_precision, 0, 0,
                                 fmt::format("seqslam len {} sep {} kmult {}", len, sep, mult)});
      }
      for (double gap : gaps) {
        for (double cap : caps) {
          for (double thr : thresholds) {
            mapping::MapConfig c;
            c.score.contrast_window = 0;  // s is already the matrix to align
            c.search.gap = static_cast<float>(gap);
            c.search.cap = cap > 0 ? std::optional<float>(static_cast<float>(cap)) : std::nullopt;
            c.significance.threshold = static_cast<float>(thr);
            c.search.min_separation = static_cast<std::size_t>(sep);
            const auto result = mapping::build_map(s, c);
            std::vector<evaluation::ScoredPair> pairs;
            for (const auto& p : result.pruning.pairs) pairs.push_back({p.i, p.j, p.score});
            const auto m = evaluation::evaluate_loop_closures(pairs, n, same_place, c.search.min_separation);
            rows.push_back({m.f1, m.auc, m.recall_at_100_precision, m.precision, m.recall,
                            fmt::format("kmult {} gap {} cap {} threshold {} sep {} ({} alignments, {:.2f} s)", mult,
                                        gap, cap > 0 ? fmt::format("{}", cap) : "none", thr, sep,
                                        result.alignments.size(), result.seconds_align)});
          }
        }
      }
    }
  }
  auto print = [](const char* title, std::vector<Row> r, auto key) {
    std::sort(r.begin(), r.end(), [&](const Row& a, const Row& b) { return key(a) > key(b); });
    fmt::print("{}\n", title);
    for (std::size_t k = 0; k < std::min<std::size_t>(8, r.size()); ++k) {
      fmt::print("  F1 {:.3f}  AUC {:.3f}  R@100P {:.3f}  P {:.3f} R {:.3f}  | {}\n", r[k].f1, r[k].auc, r[k].r100,
                 r[k].precision, r[k].recall, r[k].setting);
    }
  };
  print("seqtopo by F1", rows, [](const Row& r) { return r.f1; });
  print("seqtopo by AUC", rows, [](const Row& r) { return r.auc; });
  print("seqtopo by R@100P", rows, [](const Row& r) { return r.r100 + 1e-3 * r.f1; });
  print("baseline by best F1", baseline_rows, [](const Row& r) { return r.f1; });
  print("baseline by AUC", baseline_rows, [](const Row& r) { return r.auc; });
  return 0;
}
