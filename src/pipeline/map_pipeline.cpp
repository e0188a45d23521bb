#include "seqtopo/pipeline/map_pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/decision_notes.hpp"
#include "seqtopo/formats/odometry_csv.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/pipeline/baselines.hpp"
#include "seqtopo/pipeline/engine_choice.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/machine_memory.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_candidates.hpp"
#include "seqtopo/scale/streaming_similarity.hpp"
#include "seqtopo/significance/low_information.hpp"
#include "seqtopo/similarity/memory.hpp"
#include "seqtopo/trajectory/ekf_map.hpp"
#include "seqtopo/trajectory/pose_graph.hpp"
#include "seqtopo/trajectory/trajectory_error.hpp"
#include "stage_clock.hpp"

namespace seqtopo::pipeline {
namespace {

using detail::stage_names;
using detail::StageClock;

void say(const MapObserver& observer, const std::string& text) {
  if (observer.progress) observer.progress(text);
}

// The timing and the one progress line of the map stage, the same for every path.
void report_map(MapRun& run, const MapObserver& observer) {
  const auto& d = run.result.decisions;
  if (run.map_config.unit == align::Unit::places) {
    say(observer, fmt::format("      {:.2f} frames per place{}: contrast window {} frames, min separation {} frames",
                              d.frames_per_place, d.frames_per_place_estimated ? " (estimated)" : "", d.contrast_window,
                              d.min_separation));
  }
  for (const auto& note : formats::decision_notes(d, run.descriptor_names)) say(observer, "      " + note);
  if (d.statistics.valid()) {
    say(observer,
        fmt::format("      significance: lambda {:.3g}, K {:.3g} (from {} chance alignments); E <= {} needs a "
                    "score of {:.2f}{}, cap {:.2f}, contrast offset {:.2f}; {} removed",
                    d.statistics.lambda, d.statistics.k, d.statistics.fitted,
                    run.map_config.significance.max_e_value.value_or(0), d.score_threshold,
                    d.odometry_chance_agreement < 1
                        ? fmt::format(" where the odometry agrees (as {:.3g} of chance alignments do)",
                                      d.odometry_chance_agreement)
                        : std::string(),
                    d.cap.value_or(0), d.contrast_offset, run.result.insignificant.size()));
  }
  say(observer, fmt::format("      {} alignments ({} contradicted by odometry), {} kept, {} places, {} junctions",
                            run.result.alignments.size() + run.result.rejected.size(), run.result.rejected.size(),
                            std::count(run.result.pruning.kept.begin(), run.result.pruning.kept.end(), true),
                            run.result.map.places.size(), run.result.map.junctions.size()));
}

void check_odometry(std::span<const Pose2> odometry, std::size_t n, const std::string& subject) {
  if (!odometry.empty() && odometry.size() != n) {
    throw InputError(subject, fmt::format("has {} poses, the sequence has {} images", odometry.size(), n));
  }
}

// run.sessions from the rows of each session.
void record_sessions(std::span<const SequenceInput> inputs, const std::vector<std::size_t>& rows, MapRun& run) {
  std::size_t begin = 0;
  run.sessions.clear();
  for (std::size_t k = 0; k < rows.size() && k < inputs.size(); ++k) {
    run.sessions.push_back({inputs[k].path.string(), begin, begin + rows[k]});
    begin += rows[k];
  }
}

// The first image of each of the map's sessions after the first (the inputs' and those begun at a break found inside
// one): no topological edge from one session's last image to the next one's first.
std::vector<std::size_t> session_starts(const MapRun& run) {
  const auto sessions = run.map_sessions();
  std::vector<std::size_t> starts;
  for (std::size_t k = 1; k < sessions.size(); ++k) starts.push_back(sessions[k].begin);
  return starts;
}

// The map settings with the sessions' boundaries (session_starts).
mapping::MapConfig map_config_of(const MapSettings& settings, const MapRun& run) {
  mapping::MapConfig config = settings.map;
  config.graph.topology.session_starts = session_starts(run);
  return config;
}

// Session breaks inside the inputs (timeline/session_breaks.hpp): a long gap in a session's frame times where the
// frames either side do not look like neighbours by any of `similarities` (the raw similarity of two frames, one
// per descriptor); `masked` frames (sorted) carry no evidence. Fills run.session_breaks and says what it found.
void find_session_breaks(const std::vector<std::vector<double>>& times,
                         const std::vector<timeline::Similarity>& similarities, const std::vector<std::size_t>& masked,
                         const MapObserver& observer, MapRun& run) {
  const auto skip = [&masked](std::size_t f) { return std::binary_search(masked.begin(), masked.end(), f); };
  for (std::size_t k = 0; k < run.sessions.size() && k < times.size(); ++k) {
    const auto& session = run.sessions[k];
    if (times[k].size() != session.end - session.begin) continue;
    std::vector<timeline::TimeGap> gaps;
    try {
      gaps = timeline::time_gaps(times[k]);
    } catch (const std::invalid_argument&) {
      continue;  // times out of order (prepare_session checked those it reads): no evidence of a break
    }
    for (auto gap : gaps) {
      gap.frame += session.begin;
      const bool neighbours = std::any_of(similarities.begin(), similarities.end(), [&](const auto& similarity) {
        return timeline::looks_like_neighbours(similarity, gap.frame - 1, gap.frame, session.begin, session.end, skip);
      });
      say(observer, fmt::format("      {:.3g} s without a frame before image {} (the recording's median interval "
                                "{:.3g} s){}",
                                gap.gap, gap.frame, gap.median_interval,
                                neighbours ? ", but the images either side look like neighbours: one session"
                                           : ": a session break (no topological edge across it)"));
      if (!neighbours) run.session_breaks.push_back(gap);
    }
  }
}

// The odometry file named in errors (one session's; several sessions' odometry is checked session by session).
std::string odometry_name(const MapRequest& request) {
  return request.sessions.size() == 1 ? request.sessions.front().odometry.string() : std::string();
}

// A map needs two images; when --every or --every-metres thinned the sequence to fewer, the error says so.
[[noreturn]] void too_few_images(const MapRequest& request, std::span<const SequenceInput> inputs, std::size_t n) {
  const SequenceInput& input = inputs.front();
  std::string why = fmt::format("needs at least 2 images, got {}", n);
  const auto& every_metres = request.sessions.front().every_metres;
  if (inputs.size() == 1 && every_metres && !input.frames.empty()) {
    why += fmt::format(" (--every-metres {} kept {}; give a shorter distance)", *every_metres, n);
  } else if (inputs.size() == 1 && input.every > 1) {
    why += fmt::format(" (--every {} kept {}; give a smaller step)", input.every, n);
  }
  throw InputError(input.path.string(), why);
}

// Dark or near-uniform images carry no evidence of a revisit (significance/low_information.hpp): those of the n
// frames' grey-level entropies (none when the frames are not images).
std::vector<std::size_t> low_information_of(const std::vector<double>& entropy, std::size_t n) {
  return entropy.size() == n ? significance::low_information_frames(entropy) : std::vector<std::size_t>{};
}

// Stages 1 and 2 with the N x N matrices: one similarity matrix per descriptor, fused and aligned.
void map_dense(const MapRequest& request, std::span<const SequenceInput> inputs, InputKind kind,
               const std::vector<Pose2>& odometry, const std::vector<std::vector<double>>& times,
               const MapObserver& observer, StageClock& clock, MapRun& run) {
  const MapSettings& settings = request.settings;
  auto descriptors = settings.descriptors;
  // A descriptors.npy or similarity.npy input is one matrix, whatever descriptors were asked for.
  if (kind == InputKind::descriptors || kind == InputKind::similarity) descriptors.resize(1);
  clock.begin(" matrix");
  auto config = settings.similarity;
  if (!config.note && observer.progress) config.note = observer.progress;
  if (!config.progress) config.progress = clock.similarity_progress();
  if (observer.on_image && kind == InputKind::images) config.on_image = observer.on_image;
  // Every descriptor from one pass over the images.
  run.similarities = compute_similarities(inputs, descriptors, config);
  record_sessions(inputs, run.similarities.front().session_rows, run);
  for (std::size_t k = 0; k < run.similarities.size(); ++k) {
    run.descriptor_names.emplace_back(kind == InputKind::similarity    ? "similarity.npy"
                                      : kind == InputKind::descriptors ? "descriptors.npy"
                                                                       : descriptor_name(descriptors[k]));
    run.matrices.push_back(std::move(run.similarities[k].similarity));  // kept once, in run.matrices
    say(observer, fmt::format("      {}: {} images, kappa {:.4g}", run.descriptor_names.back(),
                              run.matrices.back().rows, run.similarities[k].kappa));
  }
  clock.end();
  const std::size_t n = run.matrices.front().rows;
  if (n < 2) too_few_images(request, inputs, n);

  clock.begin();
  check_odometry(odometry, n, odometry_name(request));
  const auto masked = low_information_of(run.similarities.front().frame_entropy, n);
  std::vector<timeline::Similarity> similarities;
  for (const auto& m : run.matrices) similarities.emplace_back([&m](std::size_t i, std::size_t j) { return m(i, j); });
  find_session_breaks(times, similarities, masked, observer, run);
  mapping::MapConfig map_config = map_config_of(settings, run);
  map_config.progress = clock.map_progress();
  run.result = mapping::build_map(run.matrices, map_config, odometry, masked);
  report_map(run, observer);
  clock.end({{"alignment", run.result.seconds_align}, {"pruning + labels + topology", 0}});
}

// similarity.png of --sparse, from the candidates alone (never the N x N cells): see its caller.
plot::MatrixOverview sparse_overview(const scale::SparseScores& scores, float offset, std::size_t max_side) {
  plot::MatrixOverview overview;
  const std::size_t n = scores.rows();
  overview.block = std::max<std::size_t>(1, (n + max_side - 1) / max_side);
  const std::size_t b = overview.block, side = (n + b - 1) / b;
  overview.cells = DenseMatrix<float>(side, side, -std::numeric_limits<float>::infinity());
  std::vector<std::size_t> stored(side * side, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto cols = scores.row_columns(i);
    const auto values = scores.row_values(i);
    for (std::size_t k = 0; k < cols.size(); ++k) {
      float& cell = overview.cells(i / b, cols[k] / b);
      cell = std::max(cell, values[k] - offset);
      ++stored[(i / b) * side + cols[k] / b];
    }
  }
  for (std::size_t r = 0; r < side; ++r) {
    for (std::size_t c = 0; c < side; ++c) {
      const std::size_t cells = (std::min(n, (r + 1) * b) - r * b) * (std::min(n, (c + 1) * b) - c * b);
      if (stored[r * side + c] < cells) overview.cells(r, c) = std::max(overview.cells(r, c), scores.background());
    }
  }
  return overview;
}

// The streamed replacement of stages 1 and 2: descriptors, then the map on scores computed when the engine
// reads them. Leaves run.result.scores empty and fills run.overview for similarity.png.
void map_streamed(const MapRequest& request, std::span<const SequenceInput> inputs, const std::vector<Pose2>& odometry,
                  const std::vector<std::vector<double>>& times, const MapObserver& observer, StageClock& clock,
                  MapRun& run) {
  const MapSettings& settings = request.settings;
  clock.begin(" (--streaming: the similarity is computed on the fly, never N x N)");
  auto similarity_config = settings.similarity;
  similarity_config.descriptor = settings.descriptors.front();
  if (!similarity_config.progress) similarity_config.progress = clock.similarity_progress();
  DescriptorResult described = compute_descriptors(inputs, similarity_config);
  const std::size_t n = described.descriptors.rows, dim = described.descriptors.cols;
  record_sessions(inputs, described.session_rows, run);
  run.descriptor_names.emplace_back(
      described.descriptor == Descriptor::npy ? "descriptors.npy" : std::string(descriptor_name(described.descriptor)));
  say(observer, fmt::format("      {}: {} images, {} dimensions", run.descriptor_names.back(), n, dim));
  if (n < 2) too_few_images(request, inputs, n);
  check_odometry(odometry, n, odometry_name(request));
  // The place scale from the raw cosine near the diagonal (or the odometry), then the windows in frames.
  mapping::MapConfig config = map_config_of(settings, run);
  std::optional<mapping::PlaceScale> place;
  std::optional<scale::StreamingSimilarity> streamed;
  const auto make_streamed = [&](std::size_t window) {
    try {
      streamed.emplace(
          described.descriptors.values, n, dim,
          scale::StreamingConfig{.contrast_window = window,
                                 .contrast_offset = 0.0F,
                                 .cache_tiles = streamed_cache_tiles(n, request.engine == MapEngine::sparse)});
    } catch (const std::invalid_argument& e) {
      throw InputError(inputs.front().path.string(), e.what());  // e.g. an all-zero descriptor has no direction
    }
  };
  if ((config.unit == align::Unit::places) && !config.frames_per_place) {
    place = mapping::place_scale(odometry, [&] {
      make_streamed(0);
      const auto& raw = *streamed;
      return mapping::estimate_frames_per_place(
          align::ScoreSource::function(n, n, [&raw](std::size_t i, std::size_t j) { return raw.cosine(i, j); }));
    });
    config.frames_per_place = place->frames_per_place;
  }
  const mapping::MapConfig framed = mapping::settings_in_frames(config, config.frames_per_place.value_or(1.0));
  make_streamed(framed.score.contrast_window);
  const auto masked = low_information_of(described.frame_entropy, n);
  const auto& cosines = *streamed;
  find_session_breaks(times, {[&cosines](std::size_t i, std::size_t j) { return cosines.cosine(i, j); }}, masked,
                      observer, run);
  config.graph.topology.session_starts = session_starts(run);
  described.descriptors = {};  // the streamed similarity keeps its own normalised copy
  // --sparse: the contrast-enhanced score at each frame's nearest neighbours (FAISS), the background elsewhere.
  std::optional<scale::SparseScores> candidates;
  if (request.engine == MapEngine::sparse) {
    scale::CandidateConfig cc;
    cc.neighbours = request.sparse.neighbours.value_or(SparseOptions::kDefaultNeighbours);
    cc.diagonal_reach = request.sparse.diagonal_reach.value_or(0);
    cc.exclude = framed.search.min_separation;
    scale::CandidateStats stats;
    candidates = scale::sparse_map_scores(*streamed, request.sparse.background, cc, &stats);
    run.sparse_pairs = stats.pairs;
    say(observer, fmt::format("      sparse: {} candidate pairs ({} nearest neighbours per frame, diagonals {} frames "
                              "around them), background {:.3g}",
                              stats.pairs, cc.neighbours, cc.diagonal_reach, request.sparse.background));
  }
  clock.end();

  // The sparse engine on the candidates minus the offset the run aligns with (the statistics stay those of the
  // streamed scores, mapping::build_map_from_enhanced).
  mapping::AlignmentRun sparse_run;
  if (candidates) {
    sparse_run = [&](const align::AlignConfig& engine, float offset, const std::vector<bool>& left_out,
                     const std::vector<bool>& masked) {
      // The frames not left out as one sequence, numbered in order (mapping::AlignmentRun).
      constexpr std::uint32_t kLeftOut = std::numeric_limits<std::uint32_t>::max();
      std::vector<std::uint32_t> index(n, kLeftOut);
      std::uint32_t kept = 0;
      for (std::size_t f = 0; f < n; ++f) {
        if (left_out.empty() || !left_out[f]) index[f] = kept++;
      }
      const auto soft = [&](std::size_t f) { return !masked.empty() && masked[f]; };
      std::vector<scale::SparseEntry> entries;
      entries.reserve(candidates->entries());
      for (std::size_t i = 0; i < n; ++i) {
        if (index[i] == kLeftOut) continue;
        const auto cols = candidates->row_columns(i);
        const auto values = candidates->row_values(i);
        for (std::size_t k = 0; k < cols.size(); ++k) {
          if (index[cols[k]] == kLeftOut) continue;
          const float v = values[k] - offset;  // soft-masked as the dense scores are
          entries.push_back({index[i], index[cols[k]], soft(i) || soft(cols[k]) ? std::min(v, 0.0F) : v});
        }
      }
      const scale::SparseScores shifted(kept, kept, candidates->background(), std::move(entries));
      return config.search.reverse ? scale::sparse_local_alignments_both(shifted, engine, settings.map.threads)
                                   : scale::sparse_local_alignments(shifted, engine);
    };
  }
  clock.begin(candidates ? " (sparse engine on the candidates)" : " (fast engine)");
  config.progress = clock.map_progress();
  run.result = mapping::build_map_from_enhanced(streamed->source(), config, odometry, sparse_run, masked);
  run.result.decisions.frames_per_place_estimated = place.has_value();
  run.result.decisions.place_scale_missing = place && !place->found;
  report_map(run, observer);
  clock.end({{"alignment (similarity streamed)", run.result.seconds_align}, {"pruning + labels + topology", 0}});

  const auto stats = streamed->stats();
  run.streamed_cells = stats.cells_computed;
  run.streamed_cache_bytes = stats.cache_bytes;

  if (candidates) {
    // The overview of the scores the sparse engine aligned: each block's largest candidate, or the background
    // where the block has cells without one (what matrix_overview would read from candidates->source()).
    clock.begin(" for similarity.png (from the candidates)");
    run.overview = sparse_overview(*candidates, run.result.decisions.contrast_offset, 2048);
    clock.end({{"similarity overview (candidates)", 0}});
    return;
  }
  clock.begin(" for similarity.png (one more streamed pass over the lower triangle)");
  // The streamed scores are 0.5 (E + E^T), symmetric bit for bit: half the reads suffice. The overview shows
  // them minus the offset the run aligned with.
  const float offset = run.result.decisions.contrast_offset;
  const auto& enhanced = *streamed;
  run.overview = plot::matrix_overview(
      align::ScoreSource(n, n,
                         [&enhanced, offset](std::size_t i, std::size_t b, std::size_t e, align::Score* out) {
                           enhanced.read_row(i, b, e, out);
                           for (std::size_t k = 0; k < e - b; ++k) out[k] -= offset;
                         }),
      {.max_side = 2048, .symmetric = true});
  clock.end({{"similarity overview (streamed)", 0}});
}

// Stages 3 and 4: the trajectory picture and the accuracy against whatever truth is given.
// The truth is loaded inside the accuracy stage (`load_truth`, may be empty), so that its time is counted there.
void trajectory_and_accuracy(const MapSettings& settings, const std::function<MapTruth()>& load_truth,
                             StageClock& clock, MapRun& run) {
  const std::size_t n = run.result.map.labels.size();
  if (!run.odometry.empty()) {
    clock.begin(" (EKF and pose graph)");
    run.ekf = trajectory::ekf_map(run.odometry, run.result.map.labels).images;
    std::vector<std::pair<std::size_t, std::size_t>> loops;
    for (const auto& p : run.result.pruning.pairs) loops.emplace_back(p.i, p.j);
    run.pose_graph = trajectory::pose_graph(run.odometry, loops);
    clock.end();
  }
  if (!load_truth) return;
  clock.begin(" against the ground truth");
  const MapTruth truth = load_truth();
  const std::size_t min_separation = run.result.decisions.min_separation;
  std::vector<bool> has_partner;  // the recall denominator, shared by seqtopo's metrics and the baseline's
  if (truth.same_place) {
    has_partner = evaluation::images_with_earlier_partner(n, truth.same_place, truth.earlier_partners, min_separation);
    std::vector<evaluation::ScoredPair> pairs;
    std::vector<double> confidence;
    std::vector<bool> correct;
    for (const auto& p : run.result.pruning.pairs) {
      pairs.push_back({p.i, p.j, static_cast<float>(p.confidence)});
      confidence.push_back(p.confidence);
      correct.push_back(truth.same_place(p.i, p.j));
    }
    run.calibration = evaluation::calibration(confidence, correct);
    run.metrics = evaluation::evaluate_loop_closures(pairs, has_partner, truth.same_place);
    run.errors = evaluation::loop_closure_errors(pairs, has_partner, truth.same_place, min_separation);
  }
  if (!truth.places.empty()) {
    if (truth.places.size() != n) throw std::invalid_argument("true places: one per image expected");
    // Merges of neighbouring true places that the loop-closure ground truth calls the same place are tolerated.
    const evaluation::Tolerated tolerated =
        truth.same_place ? evaluation::Tolerated(truth.same_place) : evaluation::Tolerated{};
    run.topology = evaluation::evaluate_topology(run.result.map.labels, run.result.map.junctions, truth.places,
                                                 truth.junctions, run.result.decisions.min_separation, 2, tolerated);
  }
  if (!truth.poses.empty() && !run.odometry.empty()) {
    if (truth.poses.size() != n) throw std::invalid_argument("true poses: one per image expected");
    run.ate = TrajectoryErrors{trajectory::absolute_trajectory_error(run.odometry, truth.poses),
                               trajectory::absolute_trajectory_error(run.ekf, truth.poses),
                               trajectory::absolute_trajectory_error(run.pose_graph, truth.poses)};
  }
  clock.end();
  if (truth.same_place) {
    if (run.streamed()) {
      run.baseline_skipped = "the SeqSLAM-style baseline needs the dense N x N matrix; not run with --streaming";
    } else {
      // The baseline runs on every matrix seqtopo saw (each descriptor's S and the fused, enhanced scores).
      std::vector<std::pair<std::string, const SimilarityMatrix*>> sources;
      for (std::size_t k = 0; k < run.matrices.size(); ++k)
        sources.emplace_back(run.descriptor_names[k], &run.matrices[k]);
      if (run.matrices.size() > 1 || settings.map.score.contrast_window > 0) {
        sources.emplace_back("seqtopo's fused scores", &run.result.scores);
      }
      clock.begin(fmt::format(" on {} matri{}", sources.size(), sources.size() == 1 ? "x" : "ces"));
      if (auto b = seqslam_loop_closure_baseline(sources, has_partner, truth.same_place, min_separation,
                                                 settings.similarity.threads)) {
        run.baseline_metrics = std::move(b->metrics);
        run.baseline_name = std::move(b->method);
      }
      clock.end();
    }
  }
}

MapRun new_run(const MapSettings& settings, std::string input, std::string preset) {
  MapRun run;
  run.input = std::move(input);
  run.preset = std::move(preset);
  run.map_config = settings.map;
  run.engine = settings.map.engine == mapping::MapConfig::Engine::fast ? MapEngine::fast : MapEngine::exact;
  run.paper_trajectory = settings.paper_trajectory;
  return run;
}

}  // namespace

MapJob::MapJob(MapRequest request) : request_(std::move(request)) {
  if (request_.sessions.empty()) throw InputError("input", "no input given");
  const std::vector<SessionSource>& sources = request_.sessions;
  for (const auto& source : sources) {
    if (!source.input.listing && !std::filesystem::exists(source.input.path)) {
      throw InputError(source.input.path.string(), "no such file or folder");
    }
    for (const auto* path : {&source.odometry, &source.times}) {
      if (!path->empty() && !std::filesystem::exists(*path)) throw InputError(path->string(), "no such file");
    }
  }
  if (!request_.report_images.empty() && !std::filesystem::is_directory(request_.report_images)) {
    throw InputError(request_.report_images.string(), "is not a folder of images");
  }
  for (const auto* path : {&request_.truth.poses, &request_.truth.places}) {
    if (!path->empty() && !std::filesystem::exists(*path)) throw InputError(path->string(), "no such file");
  }
  kind_ = resolve_input_kind(sources.front().input);
  check_request(request_, kind_);
  // The same-place truth is read (its format recognized and parsed) before any work; its size is checked below.
  if (!request_.truth.same_place.empty())
    same_place_ = read_ground_truth(request_.truth.same_place.string(), {}, request_.truth.radius);
  if (!request_.report_images.empty() &&
      (sources.size() > 1 || (kind_ != InputKind::descriptors && kind_ != InputKind::similarity))) {
    throw InputError("--images",
                     "is for one descriptors.npy or similarity.npy input (images, videos and bags show "
                     "their own images)");
  }
  for (const auto& source : sources) {
    const InputKind kind = resolve_input_kind(source.input);
    if (kind == InputKind::similarity) {
      const auto header = io::read_npy_header(source.input.path);
      if (header.shape.size() != 2 || header.shape[0] != header.shape[1]) {
        throw InputError(source.input.path.string(), "a similarity matrix for map must be square (N x N)");
      }
      if (sources.size() > 1) {
        throw InputError(source.input.path.string(),
                         "a similarity matrix cannot be one of several sessions (it has no rows for the others)");
      }
    }
    sessions_.push_back(prepare_session(source));
  }
  const bool any_odometry =
      std::any_of(sessions_.begin(), sessions_.end(), [](const PreparedSession& s) { return !s.odometry.empty(); });
  for (const auto& s : sessions_) {
    if (any_odometry && s.odometry.empty()) {
      throw InputError(s.input.path.string(),
                       "has no odometry, but another session has: give every session odometry, "
                       "or none");
    }
    odometry_.insert(odometry_.end(), s.odometry.begin(), s.odometry.end());
    inputs_.push_back(s.input);
  }
  // 360-degree panoramas get the heading-invariant descriptor (presets.hpp), decided on the first image.
  if (request_.settings.detect_panoramas && kind_ == InputKind::images && !streams(request_.engine)) {
    panorama_note_ = detect_panorama_descriptors(inputs_.front(), request_.settings.descriptors);
  }
  // Every buffer of the run counted (memory_estimate.hpp); one that cannot fit is refused here, before any work.
  std::optional<std::size_t> expected = 0;
  for (const auto& s : sessions_) {
    if (!s.frames || !expected) {
      expected.reset();
      break;
    }
    *expected += *s.frames;
  }
  if (expected && same_place_) check_same_place_size(*same_place_, *expected, truth_every());
  // A video's frames are known once it is read; the frames its container announces size the estimate.
  std::optional<std::size_t> announced = expected;
  if (!announced && kind_ == InputKind::video && inputs_.size() == 1 && inputs_.front().frames.empty()) {
    if (const auto frames = image::video_frame_count(inputs_.front().path)) {
      announced = every_kth_count(*frames, inputs_.front().every);
    }
  }
  // Sized from the first session's input (its .npy header or first image, its kept frames); the image count is
  // every session's.
  MapRequest sized = request_;
  sized.sessions.front().input = inputs_.front();
  engine_note_ = resolve_engine(sized, kind_, announced, memory_budget_bytes());
  request_.engine = sized.engine;
  request_.settings = sized.settings;
  if (announced) {
    memory_note_ = check_map_memory(sized, kind_, *announced, available_memory_bytes());
    request_.settings.similarity.note_memory_above = std::numeric_limits<std::size_t>::max();  // ours is printed
  }
}

MapRun MapJob::run(const MapObserver& observer) const {
  std::string names;
  for (const auto& s : sessions_) {
    if (!names.empty()) names += ' ';
    names += s.input.path.string();
  }
  MapRun run = new_run(request_.settings, names, request_.preset);
  if (inputs_.size() == 1) run.sequence = inputs_.front();
  if (inputs_.size() > 1) run.session_inputs = inputs_;
  if (!request_.report_images.empty() && inputs_.size() == 1 &&
      (kind_ == InputKind::descriptors || kind_ == InputKind::similarity)) {
    run.sequence = SequenceInput(request_.report_images, InputKind::images, inputs_.front().every);
  }
  for (const auto& s : sessions_) {
    for (const auto& note : s.notes) say(observer, "      " + note);
  }
  if (!memory_note_.empty()) say(observer, "      " + memory_note_);
  if (!panorama_note_.empty()) say(observer, "      " + panorama_note_);
  if (!engine_note_.empty()) say(observer, "      " + engine_note_);
  run.engine = request_.engine;
  run.odometry = odometry_;
  const auto& files = request_.truth;
  const bool poses = !files.poses.empty() && !run.odometry.empty();
  const bool any_truth = !files.same_place.empty() || !files.places.empty() || poses;
  StageClock clock(observer, run,
                   stage_names(run.streamed(), false, !odometry_.empty(), any_truth, !files.same_place.empty()));
  std::vector<std::vector<double>> times;
  for (const auto& s : sessions_) times.push_back(s.times);
  if (run.streamed()) {
    map_streamed(request_, inputs_, odometry_, times, observer, clock, run);
  } else {
    map_dense(request_, inputs_, kind_, odometry_, times, observer, clock, run);
  }
  const std::size_t n = run.result.map.labels.size();
  std::function<MapTruth()> load_truth;
  if (any_truth) {
    // A ground truth of the whole recording is thinned as --every thinned it (one input; --every-metres's frames
    // are listed as kept).
    const std::size_t every = truth_every();
    load_truth = [this, &files, n, poses, every] {
      MapTruth truth;
      if (same_place_) {
        auto same_place = same_place_truth(*same_place_, files.radius, n, every);
        truth.same_place = std::move(same_place.same_place);
        truth.earlier_partners = std::move(same_place.earlier_partners);
      }
      if (!files.places.empty()) {
        auto places = load_true_places(files.places, n, every);
        truth.places = std::move(places.places);
        truth.junctions = std::move(places.junctions);
      }
      if (poses) truth.poses = load_true_poses(files.poses, n, every);
      return truth;
    };
  }
  trajectory_and_accuracy(request_.settings, load_truth, clock, run);
  return run;
}

std::size_t MapJob::truth_every() const {
  return inputs_.size() == 1 && inputs_.front().frames.empty() ? inputs_.front().every : std::size_t{1};
}

std::vector<formats::MapSession> MapRun::map_sessions() const {
  std::vector<formats::MapSession> out;
  for (const auto& session : sessions) {
    out.push_back(session);
    for (const auto& b : session_breaks) {
      if (b.frame <= session.begin || b.frame >= session.end) continue;
      out.back().end = b.frame;
      out.push_back({session.input, b.frame, session.end, b.gap, b.median_interval});
    }
  }
  return out;
}

MapRun map_sequence(const MapRequest& request, const MapObserver& observer) { return MapJob(request).run(observer); }

MapRun map_similarities(std::vector<SimilarityMatrix> similarities, std::vector<std::string> names,
                        const MapSettings& settings, std::span<const Pose2> odometry, const MapTruth& truth,
                        const MapObserver& observer) {
  if (similarities.empty()) throw std::invalid_argument("no similarity matrix");
  if (!names.empty() && names.size() != similarities.size()) {
    throw std::invalid_argument("one name per similarity matrix expected");
  }
  MapRun run = new_run(settings, "memory", "custom");
  for (std::size_t k = 0; k < similarities.size(); ++k) {
    run.descriptor_names.push_back(names.empty() ? fmt::format("similarity {}", k) : names[k]);
  }
  run.matrices = std::move(similarities);
  const std::size_t n = run.matrices.front().rows;
  if (!odometry.empty() && odometry.size() != n) {
    throw std::invalid_argument(fmt::format("odometry has {} poses, the sequence has {} images", odometry.size(), n));
  }
  run.odometry.assign(odometry.begin(), odometry.end());
  const bool poses = !truth.poses.empty() && !run.odometry.empty();
  const bool any_truth = static_cast<bool>(truth.same_place) || !truth.places.empty() || poses;
  StageClock clock(observer, run,
                   stage_names(false, true, !run.odometry.empty(), any_truth, static_cast<bool>(truth.same_place)));
  clock.begin();
  mapping::MapConfig config = settings.map;
  config.progress = clock.map_progress();
  run.result = mapping::build_map(run.matrices, config, odometry);
  report_map(run, observer);
  clock.end({{"alignment", run.result.seconds_align}, {"pruning + labels + topology", 0}});
  std::function<MapTruth()> load_truth;
  if (any_truth) load_truth = [&truth] { return truth; };
  trajectory_and_accuracy(settings, load_truth, clock, run);
  return run;
}

}  // namespace seqtopo::pipeline
