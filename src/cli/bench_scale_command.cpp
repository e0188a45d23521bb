// `seqtopo bench scale`: time and peak memory of mapping at scale on synthetic descriptors, per stage,
// for the dense streamed similarity (every pair, never N x N in memory) and the sparse mode (nearest
// neighbour candidates), with the fitted scaling exponent of each.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_candidates.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/scale/synthetic_route.hpp"

namespace seqtopo::cli::bench_scale_command {
namespace {

using Clock = std::chrono::steady_clock;

// Resident memory of this process [bytes] (Linux /proc/self/status).
std::size_t status_bytes(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string k = key;
  while (std::getline(status, line)) {
    if (line.rfind(k, 0) == 0) return std::stoull(line.substr(k.size())) * 1024;
  }
  return 0;
}

// Peak resident memory during one stage: the kernel's high-water mark is reset where allowed
// (clear_refs), and the resident size is also sampled every 5 ms, so the figure holds either way.
class PeakSampler {
 public:
  PeakSampler() {
    std::ofstream("/proc/self/clear_refs") << "5";
    peak_ = status_bytes("VmRSS:");
    reset_ok_ = status_bytes("VmHWM:") <= peak_ + (std::size_t{1} << 20U);
    thread_ = std::thread([this] {
      std::unique_lock lock(mutex_);
      while (!stop_) {
        peak_ = std::max(peak_, status_bytes("VmRSS:"));
        wake_.wait_for(lock, std::chrono::milliseconds(5));
      }
    });
  }
  PeakSampler(const PeakSampler&) = delete;
  PeakSampler& operator=(const PeakSampler&) = delete;
  ~PeakSampler() {
    if (thread_.joinable()) stop();
  }
  std::size_t stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    return reset_ok_ ? std::max(peak_, status_bytes("VmHWM:")) : peak_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool reset_ok_ = false;
  std::size_t peak_ = 0;
  std::thread thread_;
};

// The synthetic route (scale/synthetic_route.hpp): truth[i] = the first-half frame that frame i
// revisits, or -1.
using Route = scale::SyntheticRoute;
using scale::synthetic_route;

// Fraction of revisiting frames with an aligned pair within +-2 frames of the true place.
double revisit_recall(const Route& route, const std::vector<align::LocalAlignment>& alignments) {
  std::vector<char> found(route.truth.size(), 0);
  for (const auto& a : alignments) {
    for (const auto& [i, j] : a.pairs) {
      for (const auto& [x, y] : {std::pair{i, j}, std::pair{j, i}}) {
        const long t = route.truth[x];
        if (t >= 0 && std::abs(static_cast<long>(y) - t) <= 2) found[x] = 1;
      }
    }
  }
  std::size_t total = 0, hit = 0;
  for (std::size_t i = 0; i < route.truth.size(); ++i) {
    if (route.truth[i] >= 0) {
      ++total;
      hit += static_cast<std::size_t>(found[i]);
    }
  }
  return total == 0 ? 0.0 : static_cast<double>(hit) / static_cast<double>(total);
}

// CPU time of the whole process (all threads) [s].
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Stage {
  std::string name;
  double seconds = 0;
  double cpu_seconds = 0;
  std::size_t peak_bytes = 0;
};

struct Row {
  std::string mode;
  std::size_t n = 0;
  std::vector<Stage> stages;
  std::size_t alignments = 0;
  double recall = 0;
  std::size_t candidate_pairs = 0;
  std::size_t active_cells = 0;
  std::size_t cells_computed = 0;
  std::array<double, 3> candidate_split{};  // sparse: wall seconds of index, search, exact scores  // dense: similarity
                                            // cells computed during the alignment (tiles, with recomputation)
  double total_seconds() const {
    double s = 0;
    for (const auto& st : stages) s += st.seconds;
    return s;
  }
  double total_cpu_seconds() const {
    double s = 0;
    for (const auto& st : stages) s += st.cpu_seconds;
    return s;
  }
  std::size_t peak_bytes() const {
    std::size_t p = 0;
    for (const auto& st : stages) p = std::max(p, st.peak_bytes);
    return p;
  }
};

template <typename F>
auto timed(Row& row, const std::string& name, F&& work) {
  PeakSampler sampler;
  const auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  auto result = work();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const double cpu = cpu_seconds() - c0;
  row.stages.push_back({name, seconds, cpu, sampler.stop()});
  return result;
}

struct Options {
  std::vector<std::size_t> sizes{1000, 10000, 100000};
  std::vector<std::size_t> sparse_sizes{1000, 10000, 100000, 1000000};
  std::size_t dim = 64;
  std::size_t neighbours = 10;
  float background = -1.0F;
  unsigned threads = 2;
  bool json = false;
  std::string out;  // also write the JSON here
  bool similarity_pass = true;
  std::string write_route;  // write the synthetic route of the one size in `sizes` here, and stop
};

// The alignment settings of `seqtopo map`'s defaults.
align::AlignConfig map_align_config() { return mapping::align_config(mapping::MapConfig{}); }

Row run_dense(std::size_t n, const Options& opt) {
  Row row{"dense", n, {}, 0, 0, 0, 0, 0};
  const Route route = timed(row, "descriptors", [&] { return synthetic_route(n, opt.dim, 7); });
  const auto sim = timed(row, "normalise",
                         [&] { return std::make_unique<scale::StreamingSimilarity>(route.descriptors, n, opt.dim); });
  if (opt.similarity_pass) {
    // Every score of the lower triangle the self alignment reads, once, discarded. The threads take
    // alternate rows, so they share the tiles of one band.
    timed(row, "similarity", [&] {
      const unsigned workers = std::max(1U, opt.threads != 0 ? opt.threads : std::thread::hardware_concurrency());
      std::vector<double> sinks(workers, 0.0);
      std::vector<std::thread> pool;
      for (unsigned k = 0; k < workers; ++k) {
        pool.emplace_back([&, k] {
          std::vector<float> buffer(n);
          for (std::size_t i = k; i < n; i += workers) {
            sim->read_row(i, 0, i + 1, buffer.data());
            sinks[k] += buffer[i / 2];
          }
        });
      }
      for (auto& t : pool) t.join();
      return std::accumulate(sinks.begin(), sinks.end(), 0.0);
    });
  }
  align::FastOptions fast;
  fast.threads = opt.threads;
  const auto alignments = timed(row, "alignment", [&] {
    const scale::StreamingSimilarity fresh(route.descriptors, n, opt.dim);  // a cold cache
    // Progress of a long run on stderr: similarity cells computed so far, in units of N^2.
    std::mutex m;
    std::condition_variable cv;
    bool done = false;
    std::thread progress([&] {
      std::unique_lock lock(m);
      const auto t0 = Clock::now();
      while (!cv.wait_for(lock, std::chrono::seconds(60), [&] { return done; })) {
        std::cerr << fmt::format("  dense N={}: {:.0f} s, {:.2f} x N^2 similarity cells, {:.0f} MB resident\n", n,
                                 std::chrono::duration<double>(Clock::now() - t0).count(),
                                 static_cast<double>(fresh.stats().cells_computed) / (static_cast<double>(n) * n),
                                 static_cast<double>(status_bytes("VmRSS:")) / 1048576.0);
      }
    });
    auto finish = [&] {
      {
        std::lock_guard lock(m);
        done = true;
      }
      cv.notify_all();
      progress.join();
    };
    std::vector<align::LocalAlignment> result;
    try {
      result = align::fast_local_alignments_both(fresh.source(), map_align_config(), fast);
    } catch (...) {
      finish();
      throw;
    }
    finish();
    row.cells_computed = fresh.stats().cells_computed;
    return result;
  });
  row.alignments = alignments.size();
  row.recall = revisit_recall(route, alignments);
  return row;
}

Row run_sparse(std::size_t n, const Options& opt) {
  Row row{"sparse", n, {}, 0, 0, 0, 0, 0};
  const Route route = timed(row, "descriptors", [&] { return synthetic_route(n, opt.dim, 7); });
  const auto sim = timed(row, "normalise",
                         [&] { return std::make_unique<scale::StreamingSimilarity>(route.descriptors, n, opt.dim); });
  scale::CandidateConfig cc;
  cc.neighbours = opt.neighbours;
  cc.exclude = 10;
  scale::CandidateStats cstats;
  const auto scores =
      timed(row, "candidates", [&] { return scale::sparse_map_scores(*sim, opt.background, cc, &cstats); });
  scale::SparseAlignStats astats;
  const auto alignments = timed(row, "alignment", [&] {
    return scale::sparse_local_alignments_both(scores, map_align_config(), opt.threads, &astats);
  });
  row.alignments = alignments.size();
  row.recall = revisit_recall(route, alignments);
  row.candidate_pairs = cstats.pairs;
  row.candidate_split = {cstats.seconds_index, cstats.seconds_search, cstats.seconds_scores};
  row.active_cells = astats.active_cells;
  return row;
}

// Least-squares slope of log(seconds) against log(N).
double scaling_exponent(const std::vector<Row>& rows, const std::string& mode, bool cpu) {
  std::vector<std::pair<double, double>> pts;
  for (const auto& r : rows) {
    const double t = cpu ? r.total_cpu_seconds() : r.total_seconds();
    if (r.mode == mode && t > 0) pts.emplace_back(std::log(static_cast<double>(r.n)), std::log(t));
  }
  if (pts.size() < 2) return std::nan("");
  double mx = 0, my = 0;
  for (auto [x, y] : pts) {
    mx += x;
    my += y;
  }
  mx /= static_cast<double>(pts.size());
  my /= static_cast<double>(pts.size());
  double sxy = 0, sxx = 0;
  for (auto [x, y] : pts) {
    sxy += (x - mx) * (y - my);
    sxx += (x - mx) * (x - mx);
  }
  return sxy / sxx;
}

void run(const Options& opt) {
  std::vector<Row> rows;
  for (const std::size_t n : opt.sizes) {
    if (n == 0) continue;  // "--sizes 0": no dense run
    rows.push_back(run_dense(n, opt));
    if (!opt.json) {
      std::cerr << fmt::format("dense  N={}: {:.1f} s, {:.2f} x N^2 similarity cells during the alignment\n", n,
                               rows.back().total_seconds(),
                               static_cast<double>(rows.back().cells_computed) / (static_cast<double>(n) * n));
    }
  }
  for (const std::size_t n : opt.sparse_sizes) {
    if (n == 0) continue;
    rows.push_back(run_sparse(n, opt));
    if (!opt.json) {
      const auto& r = rows.back();
      std::cerr << fmt::format(
          "sparse N={}: {:.1f} s (candidates: index {:.1f} s, search {:.1f} s, scores {:.1f} s; {} pairs)\n", n,
          r.total_seconds(), r.candidate_split[0], r.candidate_split[1], r.candidate_split[2], r.candidate_pairs);
    }
  }
  const double dense_exp = scaling_exponent(rows, "dense", false), sparse_exp = scaling_exponent(rows, "sparse", false);
  const double dense_cpu_exp = scaling_exponent(rows, "dense", true),
               sparse_cpu_exp = scaling_exponent(rows, "sparse", true);
  auto number = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
  {
    nlohmann::json out;
    out["dim"] = opt.dim;
    out["threads"] = opt.threads;
    out["neighbours"] = opt.neighbours;
    out["background"] = opt.background;
    for (const auto& r : rows) {
      nlohmann::json j;
      j["mode"] = r.mode;
      j["n"] = r.n;
      for (const auto& st : r.stages)
        j["stages"][st.name] = {
            {"seconds", st.seconds}, {"cpu_seconds", st.cpu_seconds}, {"peak_bytes", st.peak_bytes}};
      j["total_seconds"] = r.total_seconds();
      j["total_cpu_seconds"] = r.total_cpu_seconds();
      j["peak_bytes"] = r.peak_bytes();
      j["alignments"] = r.alignments;
      j["revisit_recall"] = r.recall;
      if (r.mode == "dense") j["similarity_cells_during_alignment"] = r.cells_computed;
      if (r.mode == "sparse") {
        j["candidate_pairs"] = r.candidate_pairs;
        j["candidate_seconds"] = {
            {"index", r.candidate_split[0]}, {"search", r.candidate_split[1]}, {"scores", r.candidate_split[2]}};
        j["active_cells"] = r.active_cells;
      }
      out["runs"].push_back(j);
    }
    out["scaling_exponent"] = {{"dense", number(dense_exp)}, {"sparse", number(sparse_exp)}};
    out["scaling_exponent_cpu"] = {{"dense", number(dense_cpu_exp)}, {"sparse", number(sparse_cpu_exp)}};
    if (!opt.out.empty()) std::ofstream(opt.out) << out.dump(2) << "\n";
    if (opt.json) {
      std::cout << out.dump(2) << "\n";
      return;
    }
  }
  std::cout << "| mode | N | stage: wall s / CPU s (peak MB) | total wall s | total CPU s | peak MB | alignments | "
               "revisit recall |\n";
  std::cout << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    std::string stages;
    for (const auto& st : r.stages) {
      if (!stages.empty()) stages += ", ";
      stages += fmt::format("{} {:.2f} / {:.2f} ({:.0f})", st.name, st.seconds, st.cpu_seconds,
                            static_cast<double>(st.peak_bytes) / 1048576.0);
    }
    std::cout << fmt::format("| {} | {} | {} | {:.2f} | {:.2f} | {:.0f} | {} | {:.3f} |\n", r.mode, r.n, stages,
                             r.total_seconds(), r.total_cpu_seconds(), static_cast<double>(r.peak_bytes()) / 1048576.0,
                             r.alignments, r.recall);
  }
  std::cout << fmt::format(
      "\nscaling exponent (log-log slope of total time against N): wall dense {:.2f}, sparse {:.2f}; CPU dense {:.2f}, "
      "sparse {:.2f}\n",
      dense_exp, sparse_exp, dense_cpu_exp, sparse_cpu_exp);
}

// The synthetic route as input for `seqtopo map --streaming`: descriptors.npy, and poses.csv putting a
// revisiting frame where the frame it revisits is and every other frame at its own index (so --gt-radius 2
// is the +-2 frames of the revisit recall).
void write_route(const Options& opt) {
  std::vector<std::size_t> sizes;
  for (std::size_t n : opt.sizes) {
    if (n != 0) sizes.push_back(n);
  }
  if (sizes.size() != 1) throw InputError("--write-route", "needs exactly one N in --sizes");
  const std::size_t n = sizes.front();
  const auto route = synthetic_route(n, opt.dim, 7);
  DenseMatrix<float> descriptors(n, opt.dim);
  descriptors.values = route.descriptors;
  std::string poses = "index,x,y\n";
  for (std::size_t i = 0; i < n; ++i) {
    poses += fmt::format("{},{},0\n", i, route.truth[i] >= 0 ? route.truth[i] : static_cast<long>(i));
  }
  io::OutputDirectory out(opt.write_route, {.inputs = {}, .command = "seqtopo bench scale --write-route"});
  out.write("descriptors.npy", io::encode_npy(descriptors));
  out.write("poses.csv", poses);
  out.commit();
  std::cerr << fmt::format("seqtopo bench scale: wrote {} frames ({} dimensions) to {}\n", n, opt.dim, opt.write_route);
}

void setup(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  app.add_option("--sizes", opt->sizes, "N for the dense streamed similarity (every pair); 0 = none")->delimiter(',');
  app.add_option("--sparse-sizes", opt->sparse_sizes, "N for the sparse mode (nearest-neighbour candidates); 0 = none")
      ->delimiter(',');
  add_number(app, "--dim", opt->dim, {.min = 1, .max = 1 << 20}, "descriptor dimension");
  add_number(app, "--neighbours", opt->neighbours, {.min = 1, .max = 1 << 20}, "sparse mode: candidates per frame");
  add_number(app, "--background", opt->background, {.max = 0, .max_exclusive = true},
             "sparse mode: score of every non-candidate pair (< 0)");
  add_number(app, "--threads", opt->threads, kThreads, "worker threads (0 = all cores)");
  app.add_flag("--json", opt->json, "print JSON instead of a table");
  app.add_option("--out", opt->out, "also write the JSON to this file");
  app.add_flag("!--no-similarity-pass", opt->similarity_pass,
               "dense: skip the separate similarity-only pass (alignment still computes it on the fly)");
  app.add_option("--write-route", opt->write_route,
                 "write descriptors.npy and poses.csv of the synthetic route (N from --sizes) to this folder, "
                 "for seqtopo map --streaming, and stop");
  app.callback([opt] {
    Options o = *opt;
    o.threads = resolve_threads(o.threads);
    if (!(o.background < 0)) throw InputError("--background", "must be < 0");
    if (!o.write_route.empty()) return write_route(o);
    run(o);
  });
}

const RegisterBenchCommand registered{
    {"scale", "Time and peak memory per stage at N = 10^3 .. 10^6 frames: dense streamed and sparse similarity",
     setup}};

}  // namespace
}  // namespace seqtopo::cli::bench_scale_command
