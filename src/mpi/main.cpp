// seqtopo-mpi: the sparse mode (docs/scaling.md) with its components aligned on several MPI ranks.
//
//   mpirun -np P seqtopo-mpi sparse DESCRIPTORS.npy --out alignments.json
//
// Rank 0 reads the descriptors, computes the candidates and their scores and the components of both
// passes, and deals the components out (largest box first, to the least-loaded rank). Every rank aligns
// its share with the exact engine; rank 0 gathers the alignments, merges them in the components' own
// order and writes alignments.json. The merge does not depend on where a component ran nor on the
// order the results arrive, so the file is the one of sparse_local_alignments_both in one process,
// byte for byte, for any number of ranks.
#include <fmt/format.h>
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/stopwatch.hpp"
#include "seqtopo/formats/alignment_json.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/scale/sparse_candidates.hpp"
#include "seqtopo/scale/sparse_components.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "wire.hpp"

namespace seqtopo::mpi {
namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string descriptors;
  std::string out;
  std::size_t neighbours = 10;
  float background = -1.0F;  // `seqtopo bench scale`'s sparse default
  mapping::MapConfig map;    // contrast window and offset, gap, cap, threshold, min separation
  float cap = 40.0F;         // MapConfig's
  bool no_cap = false;
  unsigned threads = 2;  // rank 0: the two passes' fills run concurrently
};

template <typename T>
MPI_Datatype datatype();
template <>
MPI_Datatype datatype<std::uint64_t>() {
  return MPI_UINT64_T;
}
template <>
MPI_Datatype datatype<std::uint32_t>() {
  return MPI_UINT32_T;
}
template <>
MPI_Datatype datatype<float>() {
  return MPI_FLOAT;
}

// MPI counts are int: long arrays go in pieces.
constexpr std::size_t chunk = std::size_t{1} << 28U;

// Waits for a request without spinning a core: a rank waiting for rank 0's preparation (FAISS and the
// scoring use every core) or for another rank's share must not take CPU time from them.
void wait_idle(MPI_Request& request) {
  int done = 0;
  MPI_Test(&request, &done, MPI_STATUS_IGNORE);
  while (done == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
  }
}

template <typename T>
void broadcast(std::vector<T>& v, int rank) {
  std::uint64_t size = v.size();
  MPI_Request request;
  MPI_Ibcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request);
  wait_idle(request);
  if (rank != 0) v.resize(size);
  for (std::size_t at = 0; at < v.size(); at += chunk) {
    const auto count = static_cast<int>(std::min(chunk, v.size() - at));
    MPI_Ibcast(v.data() + at, count, datatype<T>(), 0, MPI_COMM_WORLD, &request);
    wait_idle(request);
  }
}

template <typename T>
void send(const std::vector<T>& v, int to) {
  std::uint64_t size = v.size();
  MPI_Request request;
  MPI_Isend(&size, 1, MPI_UINT64_T, to, 0, MPI_COMM_WORLD, &request);
  wait_idle(request);
  for (std::size_t at = 0; at < v.size(); at += chunk) {
    MPI_Isend(v.data() + at, static_cast<int>(std::min(chunk, v.size() - at)), datatype<T>(), to, 0, MPI_COMM_WORLD,
              &request);
    wait_idle(request);
  }
}

template <typename T>
std::vector<T> receive(int from) {
  std::uint64_t size = 0;
  MPI_Request request;
  MPI_Irecv(&size, 1, MPI_UINT64_T, from, 0, MPI_COMM_WORLD, &request);
  wait_idle(request);
  std::vector<T> v(size);
  for (std::size_t at = 0; at < v.size(); at += chunk) {
    MPI_Irecv(v.data() + at, static_cast<int>(std::min(chunk, v.size() - at)), datatype<T>(), from, 0, MPI_COMM_WORLD,
              &request);
    wait_idle(request);
  }
  return v;
}

// Rank 0 announces whether the others may go on (1) or must stop with an exit code (its negation).
int broadcast_status(int status) {
  MPI_Request request;
  MPI_Ibcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
  wait_idle(request);
  return status;
}

// The one-line error of the seqtopo tools, from rank 0; returns the exit code.
int report(const std::exception& e) {
  if (const auto* input = dynamic_cast<const InputError*>(&e)) {
    std::cerr << "seqtopo-mpi: error: " << input->subject() << ": " << input->what() << "\n";
  } else if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
    std::cerr << "seqtopo-mpi: error: out of memory\n";
  } else {
    std::cerr << "seqtopo-mpi: error: " << e.what() << "\n";
  }
  return 1;
}

align::AlignConfig align_config(const Options& opt) {
  mapping::MapConfig map = opt.map;
  map.search.cap = opt.no_cap ? std::nullopt : std::optional<float>(opt.cap);
  return mapping::align_config(map);
}

// Rank 0's part before the alignment: descriptors -> sparse scores -> components.
struct Prepared {
  std::size_t frames = 0;
  scale::SparseScores scores;
  std::vector<scale::SparseComponent> components;
};

Prepared prepare(const Options& opt) {
  const auto descriptors = io::read_npy_matrix<float>(opt.descriptors);
  if (descriptors.rows == 0 || descriptors.cols == 0) {
    throw InputError(opt.descriptors, "no descriptors (empty array)");
  }
  scale::StreamingConfig streaming;
  streaming.contrast_window = opt.map.score.contrast_window;
  streaming.contrast_offset = opt.map.score.contrast_offset;
  std::unique_ptr<scale::StreamingSimilarity> similarity;
  try {
    similarity =
        std::make_unique<scale::StreamingSimilarity>(descriptors.values, descriptors.rows, descriptors.cols, streaming);
  } catch (const std::invalid_argument& e) {
    throw InputError(opt.descriptors, e.what());  // a zero or non-finite descriptor
  }
  scale::CandidateConfig candidates;
  candidates.neighbours = opt.neighbours;
  candidates.exclude = opt.map.search.min_separation;
  Prepared p;
  p.frames = descriptors.rows;
  p.scores = scale::sparse_map_scores(*similarity, opt.background, candidates);
  p.components = scale::sparse_components_both(p.scores, align_config(opt), opt.threads);
  return p;
}

int run(const Options& opt, int rank, int ranks) {
  const auto t_start = Clock::now();
  Prepared p;
  std::vector<std::size_t> owner;
  int status = 1;
  if (rank == 0) {
    try {
      p = prepare(opt);
      owner = scale::deal_components(p.components, static_cast<std::size_t>(ranks));
    } catch (const std::exception& e) {
      status = -report(e);
    }
  }
  if (const int s = broadcast_status(status); s <= 0) return -s;
  const double seconds_prepare = seconds_since(t_start);

  // The scores are sent, not rebuilt: rebuilding them on every rank would repeat the candidate search
  // and the exact scoring, the most expensive stage, while they are only N x 2k entries of 8 bytes.
  ScoresWire scores_wire;
  if (rank == 0) scores_wire = encode_scores(p.scores);
  double bytes_sent = 0;  // rank 0, to each other rank
  if (rank == 0) {
    bytes_sent = static_cast<double>(8 * (scores_wire.header.size() + scores_wire.row_counts.size()) +
                                     4 * (scores_wire.columns.size() + scores_wire.values.size()));
  }
  broadcast(scores_wire.header, rank);
  broadcast(scores_wire.row_counts, rank);
  broadcast(scores_wire.columns, rank);
  broadcast(scores_wire.values, rank);
  const scale::SparseScores received_scores = rank == 0 ? scale::SparseScores() : decode_scores(scores_wire);
  const scale::SparseScores& scores = rank == 0 ? p.scores : received_scores;
  scores_wire = {};

  // Each rank gets its components; rank 0 keeps its own.
  std::vector<scale::SparseComponent> mine;
  std::vector<std::vector<std::size_t>> dealt(static_cast<std::size_t>(ranks));
  if (rank == 0) {
    for (std::size_t k = 0; k < p.components.size(); ++k) dealt[owner[k]].push_back(k);
    for (int r = 1; r < ranks; ++r) {
      std::vector<const scale::SparseComponent*> share;
      for (const std::size_t k : dealt[static_cast<std::size_t>(r)]) share.push_back(&p.components[k]);
      const auto words = encode_components(share);
      bytes_sent += 8.0 * static_cast<double>(words.size()) / (ranks - 1);  // per rank, on average
      send(words, r);
    }
  } else {
    mine = decode_components(receive<std::uint64_t>(0));
  }

  const auto t_align = Clock::now();
  const double seconds_send = std::chrono::duration<double>(t_align - t_start).count() - seconds_prepare;
  const align::AlignConfig config = align_config(opt);
  std::vector<std::vector<align::LocalAlignment>> aligned;
  double box_cells = 0;
  auto align_one = [&](const scale::SparseComponent& c) {
    aligned.push_back(scale::align_component(scores, config, c));
    box_cells += static_cast<double>(c.box_cells());
  };
  if (rank == 0) {
    for (const std::size_t k : dealt[0]) align_one(p.components[k]);
  } else {
    for (const scale::SparseComponent& c : mine) align_one(c);
  }
  const double seconds_align = seconds_since(t_align);

  // Gather: alignments per component, in the order each rank was given its components.
  const auto t_gather = Clock::now();
  double bytes_gathered = 0;
  if (rank != 0) {
    AlignmentsWire wire = encode_alignments(aligned);
    send(wire.words, 0);
    send(wire.scores, 0);
  }
  std::vector<std::vector<align::LocalAlignment>> all(p.components.size());
  if (rank == 0) {
    for (std::size_t i = 0; i < dealt[0].size(); ++i) all[dealt[0][i]] = std::move(aligned[i]);
    for (int r = 1; r < ranks; ++r) {
      AlignmentsWire wire;
      wire.words = receive<std::uint64_t>(r);
      wire.scores = receive<float>(r);
      bytes_gathered += static_cast<double>(8 * wire.words.size() + 4 * wire.scores.size());
      auto lists = decode_alignments(wire);
      const auto& ks = dealt[static_cast<std::size_t>(r)];
      if (lists.size() != ks.size()) {
        throw std::logic_error("seqtopo-mpi: a rank returned the wrong number of components");
      }
      for (std::size_t i = 0; i < ks.size(); ++i) all[ks[i]] = std::move(lists[i]);
    }
  }
  double stats[3] = {seconds_align, box_cells, static_cast<double>(aligned.size())};
  std::vector<double> per_rank(rank == 0 ? 3 * static_cast<std::size_t>(ranks) : 0);
  MPI_Gather(stats, 3, MPI_DOUBLE, per_rank.data(), 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);

  const double seconds_gather = seconds_since(t_gather);

  status = 0;
  if (rank == 0) {
    try {
      const auto t_merge = Clock::now();
      const auto result = scale::merge_component_alignments_both(p.scores, config, p.components, std::move(all));
      io::write_file_atomic(opt.out, formats::alignments_to_json(result).dump(1) + "\n");
      const double seconds_merge = seconds_since(t_merge);
      std::string components, cells, seconds;
      for (int r = 0; r < ranks; ++r) {
        const double* s = &per_rank[3 * static_cast<std::size_t>(r)];
        const char* sep = r == 0 ? "" : ",";
        components += fmt::format("{}{:.0f}", sep, s[2]);
        cells += fmt::format("{}{:.0f}", sep, s[1]);
        seconds += fmt::format("{}{:.2f}", sep, s[0]);
      }
      std::cerr << fmt::format(
          "seqtopo-mpi: ranks {}, frames {}, alignments {}; components per rank {}; box cells per rank {}; "
          "sent {:.1f} MB per rank, gathered {:.1f} MB; seconds: prepare {:.2f}, send {:.2f}, align per rank {}, "
          "gather {:.2f}, merge and write {:.2f}, total {:.2f}\n",
          ranks, p.frames, result.size(), components, cells, ranks > 1 ? bytes_sent / 1e6 : 0.0, bytes_gathered / 1e6,
          seconds_prepare, seconds_send, seconds, seconds_gather, seconds_merge, seconds_since(t_start));
    } catch (const std::exception& e) {
      status = report(e);
    }
  }
  return broadcast_status(status);
}

}  // namespace

// The rank a launcher gave this process, read before MPI_Init from its environment (Open MPI, PMIx, PMI,
// MPICH's Hydra); a process started alone is rank 0.
int launched_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
    if (const char* value = std::getenv(name); value != nullptr && *value != '\0') return std::atoi(value);
  }
  return 0;
}

}  // namespace seqtopo::mpi

int main(int argc, char** argv) {
  using seqtopo::mpi::Options;
  Options opt;
  CLI::App app{"seqtopo-mpi: the sparse mode's components aligned on several MPI ranks (run it with mpirun)"};
  app.require_subcommand(1);
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  auto* sparse = app.add_subcommand(
      "sparse", "Sparse alignment of DESCRIPTORS.npy (N x D, cosine) -> alignments.json, identical to one process");
  sparse->add_option("descriptors", opt.descriptors, "N x D descriptors (.npy, float32/float64)")->required();
  sparse->add_option("--out", opt.out, "alignments.json to write")->required();
  using seqtopo::cli::add_number;
  add_number(*sparse, "--neighbours", opt.neighbours, {.min = 1, .max = 1 << 20}, "candidates per frame (k)");
  add_number(*sparse, "--background", opt.background, {.max = 0, .max_exclusive = true},
             "score of every non-candidate pair (< 0)");
  add_number(*sparse, "--contrast-window", opt.map.score.contrast_window, seqtopo::cli::kAtLeastOne,
             "contrast enhancement window [frames]");
  add_number(*sparse, "--contrast-offset", opt.map.score.contrast_offset, seqtopo::cli::kAnyFinite,
             "subtracted after enhancement [standard deviations]");
  add_number(*sparse, "--gap", opt.map.search.gap, seqtopo::cli::kPositive, "gap penalty, both sequences");
  opt.cap = opt.map.search.cap.value_or(opt.cap);
  add_number(*sparse, "--cap", opt.cap, seqtopo::cli::kPositive, "cap on the cumulative score");
  sparse->add_flag("--no-cap", opt.no_cap, "classical Smith-Waterman, no cap");
  add_number(*sparse, "--threshold", opt.map.significance.threshold, seqtopo::cli::kPositive,
             "minimum alignment score");
  add_number(*sparse, "--min-separation", opt.map.search.min_separation, seqtopo::cli::kAtLeastOne,
             "pairs closer in time never count [frames]");
  add_number(*sparse, "--threads", opt.threads, {.min = 1, .max = 2},
             "rank 0: threads for the two passes' fills (1 or 2)");
  // The command line is checked before MPI starts: a bad one costs no MPI start-up, and two singletons
  // starting at once can race on Open MPI's shared session folder ("mkdir ... File exists"). Every rank
  // parses the same arguments and stops here; the one launched as rank 0 speaks.
  const bool speaks = seqtopo::mpi::launched_rank() == 0;
  try {
    seqtopo::cli::check_all_numeric_options(app);
    app.parse(argc, argv);
    if (!(opt.background < 0)) throw seqtopo::InputError("--background", "must be < 0");
  } catch (const CLI::ParseError& e) {
    if (speaks) {
      if (e.get_exit_code() == 0) {
        app.exit(e);
      } else {
        std::cerr << "seqtopo-mpi: error: " << e.what() << " (see seqtopo-mpi --help)\n";
      }
    }
    return e.get_exit_code() == 0 ? 0 : 2;
  } catch (const seqtopo::InputError& e) {
    if (speaks) std::cerr << "seqtopo-mpi: error: " << e.subject() << ": " << e.what() << "\n";
    return 1;
  }
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int code = 0;
  try {
    code = seqtopo::mpi::run(opt, rank, ranks);
  } catch (const seqtopo::InputError& e) {
    if (rank == 0) std::cerr << "seqtopo-mpi: error: " << e.subject() << ": " << e.what() << "\n";
    code = 1;
  } catch (const std::exception& e) {
    // Past the first exchange a failure on one rank would leave the others waiting.
    std::cerr << "seqtopo-mpi: error: rank " << rank << ": " << e.what() << "\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return code;
}
