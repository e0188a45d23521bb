// Localization on Nordland (summer vs winter, 1,800 frames each): (a) single-frame best match with each
// descriptor, (b) the SeqSLAM-style sequence search, (c) seqtopo's alignment. Prints one Markdown table with
// recall@1 (+-tolerance frames), AUC, recall at 100% precision and the seconds of each method, and the
// time ratio of seqtopo against the SeqSLAM run measured here. Times are CPU seconds on one core.
//
//   bench_localize_nordland [--data DIR] [--tolerance 2] [--offset F] [--gap G] [--cap C|none] [--threshold T]
//                           [--window W] [--score-window W] [--online] [--cache DIR] [--skip-baselines]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "seqtopo/baseline/seqslam.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/localize/online_localizer.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

namespace {

using namespace seqtopo;

// CPU seconds of the calling thread: every method runs on one core, and the machine may be shared, so
// wall-clock time would measure the neighbours as much as the method.
struct CpuTime {
  double seconds = 0;
};
CpuTime cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return {static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec)};
}
double seconds_since(CpuTime t) { return cpu_now().seconds - t.seconds; }

struct Row {
  std::string method;
  evaluation::LocalizationMetrics metrics;
  double seconds = 0;
};

evaluation::LocalizationMetrics evaluate(const std::vector<localize::FrameMatch>& frames, std::size_t map_frames,
                                         std::size_t tolerance) {
  std::vector<evaluation::LocalizationPrediction> p(frames.size());
  for (std::size_t q = 0; q < frames.size(); ++q) {
    if (frames[q].covered) p[q].map = frames[q].map;
    p[q].score = frames[q].score;
    p[q].candidates = frames[q].candidates;
  }
  return evaluation::evaluate_localization(p, evaluation::LocalizationTruth::same_index(frames.size(), map_frames),
                                           tolerance);
}

// With a cache folder the matrices are kept between runs (for tuning; their seconds then read 0).
pipeline::SimilarityResult compute_matrix(const std::filesystem::path& query, const std::filesystem::path& map,
                                          pipeline::Descriptor d, const std::filesystem::path& cache) {
  const auto cached = cache.empty() ? cache
                                    : cache / (query.filename().string() + "_x_" + map.filename().string() + "_" +
                                               std::string(pipeline::descriptor_name(d)) + ".npy");
  if (!cached.empty() && std::filesystem::exists(cached)) {
    pipeline::SimilarityResult r;
    r.similarity = io::read_npy_matrix<float>(cached);
    return r;
  }
  pipeline::SimilarityConfig c;
  c.descriptor = d;
  c.threads = 1;
  auto r = pipeline::compute_similarity(pipeline::SequenceInput{query}, pipeline::SequenceInput{map}, c);
  if (!cached.empty()) {
    std::filesystem::create_directories(cache);
    io::write_npy(cached, r.similarity);
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path data = std::filesystem::path(__FILE__).parent_path() / "../../shared/data/nordland-64x32";
  std::filesystem::path cache;
  std::size_t tolerance = 2;
  localize::LocalizeConfig config;
  bool online = false, skip_baselines = false;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto next = [&]() -> std::string {
      if (k + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++k];
    };
    if (a == "--data")
      data = next();
    else if (a == "--cache")
      cache = next();
    else if (a == "--tolerance")
      tolerance = std::stoul(next());
    else if (a == "--offset")
      config.contrast_offset = std::stof(next());
    else if (a == "--gap")
      config.gap = std::stof(next());
    else if (a == "--cap") {
      const auto v = next();
      config.cap = v == "none" ? std::nullopt : std::optional<float>(std::stof(v));
    } else if (a == "--threshold")
      config.threshold = std::stof(next());
    else if (a == "--window")
      config.contrast_window = std::stoul(next());
    else if (a == "--score-window")
      config.score_window = std::stoul(next());
    else if (a == "--online")
      online = true;
    else if (a == "--skip-baselines")
      skip_baselines = true;  // for tuning
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }

  baseline::SeqSlamConfig seqslam;
  seqslam.sequence_length = 30;
  seqslam.min_velocity = 0.9F;
  seqslam.max_velocity = 1.6F;
  seqslam.velocity_steps = 8;
  seqslam.contrast_window = 10;
  seqslam.threads = 1;

  std::printf("| map | query | method | R@1 (+-%zu) | R@5 | AUC | R@100P | seconds | vs SeqSLAM |\n", tolerance);
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [map_name, query_name] : {std::pair{"summer", "winter"}, std::pair{"winter", "summer"}}) {
    std::vector<Row> rows;
    const auto map_dir = data / map_name, query_dir = data / query_name;
    auto t = cpu_now();
    const pipeline::SimilarityResult patch = compute_matrix(query_dir, map_dir, pipeline::Descriptor::patch, cache);
    const double patch_seconds = seconds_since(t);
    const std::size_t m = patch.similarity.cols;

    double seqslam_seconds = 1;
    if (!skip_baselines) {
      t = cpu_now();
      const pipeline::SimilarityResult hist =
          compute_matrix(query_dir, map_dir, pipeline::Descriptor::joint_histogram, cache);
      auto frames = localize::single_frame_matches(hist.similarity);
      rows.push_back({"single frame, joint histogram (chi2)", evaluate(frames, m, tolerance), seconds_since(t)});
      t = cpu_now();
      frames = localize::single_frame_matches(patch.similarity);
      rows.push_back({"single frame, patch-normalised 64x32 (SAD)", evaluate(frames, m, tolerance),
                      seconds_since(t) + patch_seconds});

      t = cpu_now();
      const auto seq = baseline::seqslam_matches(patch.similarity, seqslam);
      seqslam_seconds = seconds_since(t);
      std::vector<localize::FrameMatch> seq_frames(seq.size());
      for (std::size_t q = 0; q < seq.size(); ++q) {
        seq_frames[q].covered = seq[q].valid;
        seq_frames[q].map = seq[q].match;
        seq_frames[q].score = seq[q].score;
        seq_frames[q].candidates = {seq[q].match};
      }
      rows.push_back({"SeqSLAM (len 30, v 0.9-1.6, 8 steps)", evaluate(seq_frames, m, tolerance), seqslam_seconds});
      // The usual protocol: a query frame without a whole sequence of 30 frames behind it is not matched
      // (the search above still answers them, from shorter sequences, with inflated scores).
      for (std::size_t q = 0; q + 1 < seqslam.sequence_length && q < seq_frames.size(); ++q)
        seq_frames[q].covered = false;
      rows.push_back({"SeqSLAM, full sequences only", evaluate(seq_frames, m, tolerance), seqslam_seconds});
      // Where SeqSLAM is most confident (explains its recall at 100% precision).
      std::vector<std::size_t> order(seq.size());
      for (std::size_t q = 0; q < order.size(); ++q) order[q] = q;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seq[a].score > seq[b].score; });
      for (std::size_t k = 0; k < 3 && k < order.size(); ++k) {
        std::fprintf(stderr, "SeqSLAM top %zu: query %zu -> map %zu, score %.3f\n", k + 1, order[k],
                     seq[order[k]].match, static_cast<double>(seq[order[k]].score));
      }
    }

    t = cpu_now();
    const auto result = localize::localize_sequence(patch.similarity, config);
    rows.push_back({"seqtopo localize (alignment)", evaluate(result.frames, m, tolerance), seconds_since(t)});
    std::fprintf(stderr, "%s -> %s: %zu alignments\n", query_name, map_name, result.alignments.size());

    if (online) {
      t = cpu_now();
      const auto est = localize::online_estimates(patch.similarity, config);
      std::vector<localize::FrameMatch> on(est.size());
      for (std::size_t q = 0; q < est.size(); ++q) {
        on[q].covered = est[q].in_map;
        on[q].map = est[q].map;
        on[q].score = est[q].confidence;
        on[q].candidates = {est[q].map};
      }
      rows.push_back({"seqtopo localize --online", evaluate(on, m, tolerance), seconds_since(t)});
    }

    for (const auto& r : rows) {
      const bool matrix_included = r.method.rfind("single", 0) == 0;
      std::printf("| %s | %s | %s | %.3f | %.3f | %.3f | %.3f | %.3f%s | %s |\n", map_name, query_name,
                  r.method.c_str(), r.metrics.recall_at_1, r.metrics.recall_at_5, r.metrics.auc,
                  r.metrics.recall_at_100_precision, r.seconds, matrix_included ? " (incl. matrix)" : "",
                  matrix_included ? "" : (std::to_string(r.seconds / seqslam_seconds).substr(0, 5) + "x").c_str());
    }
    std::printf("| %s | %s | (similarity matrix, patch SAD, shared by SeqSLAM and seqtopo) | | | | | %.3f | |\n",
                map_name, query_name, patch_seconds);
    std::fflush(stdout);
  }
  return 0;
}
