// `seqtopo bench generalization`: the default pipeline on sequences nobody tuned on, with known truth
// (simulator/descriptor_sequences.hpp): pure noise of several dimensions and a drifting random walk, where
// every loop closure is false; and revisits planted forward and backward, short and long, at noise levels
// where a single-frame matcher is right from a third of the time to nearly always. Each case is mapped by the
// library's pipeline (pipeline::map_similarities, the code behind `seqtopo map descriptors.npy`) and scored
// next to the SeqSLAM-style baseline on the same matrices. The frame-rate cases on real images are
// bench/frame_rates.py, the corridor's other-camera variants bench/corridor_variants.py.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/simulator/descriptor_sequences.hpp"

namespace seqtopo::cli::bench_generalization_command {
namespace {

struct Options {
  std::size_t seeds = 5;
  std::vector<std::size_t> null_sizes{2000, 6000};
  std::size_t planted_size = 2000;
  bool json = false;
  unsigned threads = 0;
  std::string only;  // run only the cases whose name contains this
};

struct Case {
  std::string name;
  simulator::DescriptorSequenceConfig sequence;
  bool planted = false;
};

struct Outcome {
  Case c;
  double f1 = 0, precision = 0, recall = 0, baseline_f1 = 0, nearest_right = 0, seconds = 0;
  std::size_t closures = 0, false_closures = 0;
  double offset = 0, frames_per_place = 0;
};

std::string texture_name(simulator::Texture t) {
  switch (t) {
    case simulator::Texture::white:
      return "noise";
    case simulator::Texture::walk:
      return "walk";
    case simulator::Texture::ar1:
      return "ar1";
  }
  return "?";
}

// The fraction of planted frames whose single most similar frame (cosine, outside the separation band) is
// within 1 frame of the truth: how hard the revisit is for a single-frame matcher.
double nearest_neighbour_right(const simulator::DescriptorSequence& s, const SimilarityMatrix& similarity,
                               std::size_t min_separation) {
  std::size_t planted = 0, right = 0;
  const std::size_t n = similarity.rows;
  for (std::size_t i = 0; i < n; ++i) {
    if (s.position[i] == static_cast<double>(i)) continue;  // not a planted frame
    ++planted;
    std::size_t best = i;
    float best_s = -1e30F;
    for (std::size_t j = 0; j < n; ++j) {
      if ((i > j ? i - j : j - i) < min_separation) continue;
      if (similarity(i, j) > best_s) {
        best_s = similarity(i, j);
        best = j;
      }
    }
    right += std::abs(s.position[best] - s.position[i]) <= 1.5 ? 1 : 0;
  }
  return planted ? static_cast<double>(right) / static_cast<double>(planted) : 0.0;
}

Outcome run_case(const Case& c, unsigned threads) {
  const auto start = std::chrono::steady_clock::now();
  const auto sequence = simulator::make_descriptor_sequence(c.sequence);
  pipeline::MapSettings settings = pipeline::map_preset("default");
  settings.similarity.threads = threads;
  settings.map.threads = std::min(2U, threads);
  auto similarity = pipeline::similarity_of_descriptors(sequence.descriptors, nullptr, settings.similarity);
  Outcome o;
  o.c = c;
  if (c.planted) o.nearest_right = nearest_neighbour_right(sequence, similarity.similarity, 10);
  pipeline::MapTruth truth;
  const auto position = sequence.position;
  truth.same_place = [position](std::size_t i, std::size_t j) { return std::abs(position[i] - position[j]) <= 1.5; };
  std::vector<SimilarityMatrix> matrices;
  matrices.push_back(std::move(similarity.similarity));
  const auto run = pipeline::map_similarities(std::move(matrices), {"descriptors"}, settings, {}, truth);
  o.f1 = run.metrics->f1;
  o.precision = run.metrics->precision;
  o.recall = run.metrics->recall;
  o.baseline_f1 = run.baseline_metrics ? run.baseline_metrics->f1 : 0.0;
  o.closures = run.result.pruning.pairs.size();
  for (const auto& p : run.result.pruning.pairs) o.false_closures += truth.same_place(p.i, p.j) ? 0 : 1;
  o.offset = run.result.decisions.contrast_offset;
  o.frames_per_place = run.result.decisions.frames_per_place;
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

std::vector<Case> cases(const Options& o) {
  std::vector<Case> out;
  for (std::uint64_t seed = 1; seed <= o.seeds; ++seed) {
    for (std::size_t n : o.null_sizes) {
      for (std::size_t dim : {16, 128, 2048}) {
        Case c{fmt::format("null noise N={} D={}", n, dim), {}, false};
        c.sequence.frames = n;
        c.sequence.dim = dim;
        c.sequence.seed = seed;
        out.push_back(c);
      }
      Case walk{fmt::format("null walk N={} D=128", n), {}, false};
      walk.sequence.frames = n;
      walk.sequence.texture = simulator::Texture::walk;
      walk.sequence.seed = seed;
      out.push_back(walk);
    }
    const std::size_t n = o.planted_size;
    for (std::size_t length : {50, 200, 1000}) {
      for (bool reverse : {false, true}) {
        for (double noise : {2.0, 3.0, 4.0, 5.0}) {
          const std::size_t room = n / 2 - std::min(n / 2, length);
          simulator::PlantedRevisit r{room / 2, n / 2 + room / 2, length, reverse, noise};
          out.push_back({fmt::format("planted {} L={} noise {}", reverse ? "reverse" : "forward", length, noise),
                         {.frames = n, .dim = 128, .revisits = {r}, .seed = seed},
                         true});
        }
      }
    }
  }
  return out;
}

void run(const Options& o) {
  const unsigned threads = resolve_threads(o.threads);
  std::vector<Outcome> outcomes;
  for (const auto& c : cases(o)) {
    if (c.name.find(o.only) == std::string::npos) continue;
    outcomes.push_back(run_case(c, threads));
    const auto& r = outcomes.back();
    std::cerr << fmt::format(
        "seqtopo bench generalization: seed {} {}: F1 {:.3f} (baseline {:.3f}), {} closures "
        "({} false), offset {:.2f}, {:.1f} s\n",
        c.sequence.seed, c.name, r.f1, r.baseline_f1, r.closures, r.false_closures, r.offset, r.seconds);
  }
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : outcomes) {
    j.push_back({{"case", r.c.name},
                 {"seed", r.c.sequence.seed},
                 {"texture", texture_name(r.c.sequence.texture)},
                 {"planted", r.c.planted},
                 {"f1", r.f1},
                 {"precision", r.precision},
                 {"recall", r.recall},
                 {"baseline_f1", r.baseline_f1},
                 {"nearest_neighbour_right", r.nearest_right},
                 {"closures", r.closures},
                 {"false_closures", r.false_closures},
                 {"contrast_offset", r.offset},
                 {"frames_per_place", r.frames_per_place},
                 {"seconds", r.seconds}});
  }
  if (o.json) {
    std::cout << j.dump(1) << "\n";
    return;
  }
  // One line per case name: worst and mean over the seeds.
  std::vector<std::string> names;
  for (const auto& r : outcomes) {
    if (std::find(names.begin(), names.end(), r.c.name) == names.end()) names.push_back(r.c.name);
  }
  std::cout << "| case | seeds | single-frame NN right | F1 mean / worst | SeqSLAM-style F1 mean | false closures |\n"
               "|---|---|---|---|---|---|\n";
  for (const auto& name : names) {
    double f1 = 0, worst = 1, base = 0, nn = 0;
    std::size_t count = 0, wrong = 0;
    bool planted = false;
    for (const auto& r : outcomes) {
      if (r.c.name != name) continue;
      f1 += r.f1;
      worst = std::min(worst, r.f1);
      base += r.baseline_f1;
      nn += r.nearest_right;
      wrong += r.false_closures;
      planted = r.c.planted;
      ++count;
    }
    const double k = static_cast<double>(count);
    std::cout << (planted ? fmt::format("| {} | {} | {:.2f} | {:.3f} / {:.3f} | {:.3f} | {} |\n", name, count, nn / k,
                                        f1 / k, worst, base / k, wrong)
                          : fmt::format("| {} | {} | - | - | - | {} |\n", name, count, wrong));
  }
}

const RegisterBenchCommand registered{
    {"generalization",
     "The default map on synthetic sequences with known truth: pure noise, a drifting walk, planted revisits",
     [](CLI::App& app) {
       auto o = std::make_shared<Options>();
       add_number(app, "--seeds", o->seeds, kAtLeastOne, "seeds per case");
       app.add_option("--null-sizes", o->null_sizes, "frames of the pure-noise cases")->delimiter(',');
       add_number(app, "--planted-size", o->planted_size, NumberLimits{.min = 200}, "frames of the planted cases");
       app.add_flag("--json", o->json, "print one JSON array of the cases instead of the table");
       app.add_option("--cases", o->only, "run only the cases whose name contains this (e.g. 'planted reverse L=50')");
       add_number(app, "--threads", o->threads, kThreads, "worker threads (0 = all cores)");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::bench_generalization_command
