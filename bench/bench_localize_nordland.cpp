// Localization on Nordland (summer vs winter, 1,800 frames each): (a) single-frame best match with each
// descriptor, (b) the SeqSLAM-style sequence search, (c) seqtopo's alignment. Prints one Markdown table with
// recall@1 (+-tolerance frames), AUC, recall at 100% precision and the seconds of each method, and the
// time ratio of seqtopo against the SeqSLAM run measured here. Times are CPU seconds on one core.
//
//   bench_localize_nordland [--data DIR] [--tolerance 2] [--offset F] [--gap G] [--cap C|none] [--threshold T]
//                           [--window W] [--score-window W] [--max-alignments K] [--online] [--cache DIR]
//                           [--skip-baselines]
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
#include "seqtopo/pipeline/baselines.hpp"
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

// Every frame's guess counts, ranked by its confidence (online: from the frames so far).
evaluation::LocalizationMetrics evaluate(const std::vector<localize::FrameMatch>& frames, std::size_t map_frames,
                                         std::size_t tolerance) {
  std::vector<evaluation::LocalizationPrediction> p(frames.size());
  for (std::size_t q = 0; q < frames.size(); ++q) {
    p[q].map = frames[q].map;
    p[q].score = static_cast<float>(frames[q].confidence);
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
  config.tolerance = tolerance;
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
      config.tolerance = tolerance = std::stoul(next());
    else if (a == "--offset")
      config.score.contrast_offset = std::stof(next());
    else if (a == "--gap")
      config.search.gap = std::stof(next());
    else if (a == "--cap") {
      const auto v = next();
      config.search.cap = v == "none" ? std::nullopt : std::optional<float>(std::stof(v));
    } else if (a == "--threshold")
      config.significance.threshold = std::stof(next());
    else if (a == "--window")
      config.score.contrast_window = std::stoul(next());
    else if (a == "--max-alignments")
      config.max_alignments = std::stoul(next());
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

  const baseline::SeqSlamConfig seqslam = pipeline::localization_seqslam_config(1);
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
      const evaluation::LocalizationTruth truth = evaluation::LocalizationTruth::same_index(m, m);
      rows.push_back(
          {"single frame, joint histogram (chi2)",
           evaluation::evaluate_localization(pipeline::single_frame_localization(hist.similarity), truth, tolerance),
           seconds_since(t)});
      t = cpu_now();
      const auto single = pipeline::single_frame_localization(patch.similarity);
      rows.push_back({"single frame, patch-normalised 64x32 (SAD)",
                      evaluation::evaluate_localization(single, truth, tolerance), seconds_since(t) + patch_seconds});
      // SeqSLAM as `seqtopo localize --gt` runs it (pipeline/baselines.hpp): a query frame without a whole
      // sequence behind it is not matched.
      t = cpu_now();
      const auto seq = pipeline::seqslam_localization(patch.similarity, seqslam);
      seqslam_seconds = seconds_since(t);
      rows.push_back({"SeqSLAM (len 30, v 0.9-1.6, 8 steps)", evaluation::evaluate_localization(seq, truth, tolerance),
                      seqslam_seconds});
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
        on[q].score = est[q].score;
        on[q].confidence = est[q].confidence;
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
