// seqtopo._core: the compiled half of the Python package (python/seqtopo/__init__.py wraps it).
//
// Every long computation runs with the GIL released; the NumPy arrays it reads are held by the call's own
// references, so they stay alive meanwhile (a caller that writes to an input array from another thread during
// a call gets undefined results, as with any buffer shared across threads).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/outputs/localize_outputs.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/localize_pipeline.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/similarity/memory.hpp"
#include "seqtopo/similarity/similarity_from_distance.hpp"
#include "seqtopo/strings/localization.hpp"

namespace seqtopo::python {
namespace {

using Index = std::int64_t;

Index index(std::size_t i) { return static_cast<Index>(i); }

// (score, direction, a_begin, a_end, b_begin, b_end, pairs) per alignment; __init__.py makes them Alignment objects.
py::list alignments_list(const std::vector<align::LocalAlignment>& alignments) {
  py::list out;
  for (const auto& a : alignments) {
    out.append(py::make_tuple(a.score, std::string(align::to_string(a.direction)), index(a.a_begin), index(a.a_end),
                              index(a.b_begin), index(a.b_end), pairs_array(a.pairs)));
  }
  return out;
}

template <typename T>
py::array_t<Index> index_array(const std::vector<T>& values) {
  std::vector<Index> out(values.begin(), values.end());
  return to_array(std::move(out));
}

py::array_t<bool> bool_array(const std::vector<bool>& values) {
  py::array_t<bool> out(static_cast<py::ssize_t>(values.size()));
  auto view = out.mutable_unchecked<1>();
  for (std::size_t k = 0; k < values.size(); ++k) view(static_cast<py::ssize_t>(k)) = values[k];
  return out;
}

// ---- align -------------------------------------------------------------------------------------------

py::list align_scores(const py::handle& scores, align::AlignConfig config, bool reverse, unsigned threads) {
  const MatrixView view = matrix_view(scores, "scores");
  std::vector<align::LocalAlignment> alignments;
  {
    const py::gil_scoped_release release;
    require_finite(view, "scores");
    // The engine reads the array's own buffer (no copy for a float32 C-contiguous array).
    const auto source = align::ScoreSource::dense(std::span<const float>(view.data, view.size()), view.rows, view.cols);
    config.direction = align::Direction::forward;
    alignments =
        reverse ? align::local_alignments_both(source, config, threads) : align::local_alignments(source, config);
  }
  return alignments_list(alignments);
}

// ---- build_map ---------------------------------------------------------------------------------------

py::dict map_result(mapping::MapResult&& r) {
  py::dict out;
  auto& map = r.map;
  out["alignments"] = alignments_list(r.alignments);
  out["kept"] = bool_array(r.pruning.kept);
  out["retained_count"] = index_array(r.pruning.retained_count);
  std::vector<Index> closures, alignment_of;
  std::vector<float> closure_scores;
  std::vector<double> closure_confidences;
  for (const auto& p : r.pruning.pairs) {
    closures.push_back(index(p.i));
    closures.push_back(index(p.j));
    alignment_of.push_back(index(p.alignment));
    closure_scores.push_back(p.score);
    closure_confidences.push_back(p.confidence);
  }
  const auto pairs = static_cast<py::ssize_t>(alignment_of.size());
  out["loop_closures"] = to_array(std::move(closures), {pairs, 2});
  out["loop_closure_scores"] = to_array(std::move(closure_scores));
  out["loop_closure_confidences"] = to_array(std::move(closure_confidences));
  out["loop_closure_alignments"] = to_array(std::move(alignment_of));
  out["labels"] = to_array(std::move(map.labels));
  py::list places;
  for (const auto& p : map.places) places.append(index_array(p.images));
  out["places"] = places;
  std::vector<Index> edges;
  for (const auto& [p, q] : map.edges) {
    edges.push_back(p);
    edges.push_back(q);
  }
  out["edges"] = to_array(std::move(edges), {static_cast<py::ssize_t>(map.edges.size()), 2});
  out["junctions"] = index_array(map.junctions);
  py::list segments;
  for (const auto& s : map.segments) segments.append(index_array(s.places));
  out["segments"] = segments;
  out["scores"] = to_array(std::move(r.scores));
  out["seconds_align"] = r.seconds_align;
  out["seconds_prune_label"] = r.seconds_prune_label;
  return out;
}

py::dict build_map(const py::sequence& similarities, const mapping::MapConfig& config) {
  std::vector<MatrixView> views;
  for (std::size_t k = 0; k < similarities.size(); ++k) {
    views.push_back(matrix_view(similarities[k], similarities.size() == 1 ? "similarity" : "similarities"));
  }
  mapping::MapResult result;
  {
    const py::gil_scoped_release release;
    std::vector<SimilarityMatrix> matrices;
    for (const auto& view : views) {
      require_finite(view, similarities.size() == 1 ? "similarity" : "similarities");
      matrices.push_back(to_matrix(view));  // build_map works on matrices it owns: one copy
    }
    result = mapping::build_map(matrices, config);
  }
  return map_result(std::move(result));
}

// ---- localize ----------------------------------------------------------------------------------------

py::dict localize(const py::handle& query_x_map, const localize::LocalizeConfig& config) {
  const MatrixView view = matrix_view(query_x_map, "similarity");
  localize::LocalizeResult result;
  {
    const py::gil_scoped_release release;
    result = localize::localize_sequence(to_matrix(view), config);
  }
  const std::size_t frames = result.frames.size();
  const std::size_t width = config.candidates;
  std::vector<Index> map(frames, -1), candidates(frames * width, -1);
  std::vector<float> score(frames);
  std::vector<double> confidence(frames), e_value(frames);
  std::vector<bool> covered(frames), reverse(frames);
  for (std::size_t q = 0; q < frames; ++q) {
    const auto& f = result.frames[q];
    map[q] = index(f.map);
    score[q] = f.score;
    confidence[q] = f.confidence;
    e_value[q] = f.e_value;
    covered[q] = f.covered;
    reverse[q] = f.direction == align::Direction::reverse;
    for (std::size_t k = 0; k < f.candidates.size() && k < width; ++k)
      candidates[q * width + k] = index(f.candidates[k]);
  }
  py::dict out;
  out["map"] = to_array(std::move(map));
  out["score"] = to_array(std::move(score));
  out["confidence"] = to_array(std::move(confidence));
  out["e_value"] = to_array(std::move(e_value));
  out["covered"] = bool_array(covered);
  out["reverse"] = bool_array(reverse);
  out["candidates"] =
      to_array(std::move(candidates), {static_cast<py::ssize_t>(frames), static_cast<py::ssize_t>(width)});
  out["alignments"] = alignments_list(result.alignments);
  return out;
}

// ---- similarity --------------------------------------------------------------------------------------

py::dict similarity_result(pipeline::SimilarityResult&& r) {
  py::dict out;
  out["similarity"] = to_array(std::move(r.similarity));
  out["kappa"] = r.kappa;
  out["kappa_auto"] = r.kappa_auto;
  out["kappa_fraction"] = r.kappa_fraction;
  out["metric"] =
      r.distance ? py::object(py::str(std::string(similarity::distance_name(*r.distance)))) : py::object(py::none());
  out["frame_names"] = r.frame_names;
  out["column_names"] = r.column_names;
  return out;
}

void check_kappa(const std::optional<float>& kappa) {
  if (kappa && (!(*kappa > 0) || !std::isfinite(*kappa))) throw std::invalid_argument("kappa must be positive");
}

// What `seqtopo similarity descriptors.npy` computes, from arrays: rows are items; S = 1 - kappa * D.
py::dict similarity_of_descriptors(const py::handle& descriptors, const py::handle& against,
                                   const std::optional<std::string>& metric_name, std::optional<float> kappa,
                                   unsigned threads, const similarity::KappaRule& rule) {
  pipeline::SimilarityConfig config;
  if (metric_name) config.distance = similarity::parse_distance(*metric_name);
  check_kappa(kappa);
  config.kappa = kappa;
  config.threads = threads;
  config.kappa_rule = rule;
  const MatrixView a = matrix_view(descriptors, "descriptors");
  std::optional<MatrixView> b;
  if (!against.is_none()) b = matrix_view(against, "against");
  pipeline::SimilarityResult r;
  {
    const py::gil_scoped_release release;
    const SimilarityMatrix ma = to_matrix(a);
    const std::optional<SimilarityMatrix> mb = b ? std::optional(to_matrix(*b)) : std::nullopt;
    r = pipeline::similarity_of_descriptors(ma, mb ? &*mb : nullptr, config);
  }
  return similarity_result(std::move(r));
}

// The image pipeline on a folder, video, descriptors.npy or similarity.npy (image/similarity_pipeline.hpp).
py::dict similarity_of_path(const std::filesystem::path& path, const std::optional<std::filesystem::path>& against,
                            const std::string& descriptor, const std::optional<std::string>& metric_name,
                            std::optional<float> kappa, const std::string& input_kind, std::size_t every,
                            unsigned threads, const similarity::KappaRule& rule) {
  pipeline::SimilarityConfig config;
  config.descriptor = pipeline::parse_descriptor(descriptor);
  if (metric_name) config.distance = similarity::parse_distance(*metric_name);
  check_kappa(kappa);
  config.kappa = kappa;
  config.threads = threads;
  config.kappa_rule = rule;
  const auto kind = pipeline::parse_input_kind(input_kind);
  pipeline::SimilarityResult r;
  {
    const py::gil_scoped_release release;
    const pipeline::SequenceInput a{path, kind, every};
    r = against ? pipeline::compute_similarity(a, pipeline::SequenceInput{*against, kind, every}, config)
                : pipeline::compute_similarity(a, config);
  }
  return similarity_result(std::move(r));
}

// ---- progress: the pipeline's stage events handed to a Python callable ------------------------------------

// The callable gets (kind, stage, stages, name, done, total, unit, seconds) for each event of
// pipeline/progress.hpp (seqtopo.ProgressEvent is made of them on the Python side). The events come from the job's
// threads with the GIL released, so each call takes the GIL. An exception raised by the callable (a
// KeyboardInterrupt among them) cannot cross the C++ job: later events are dropped and it is raised when the job
// returns. Constructed and destroyed with the GIL held.
class PythonProgress {
 public:
  explicit PythonProgress(py::object callback) : callback_(std::move(callback)) {}
  pipeline::MapObserver observer() {
    pipeline::MapObserver o;
    if (!callback_.is_none()) o.stage = [this](const pipeline::StageEvent& e) { send(e); };
    return o;
  }
  // After the job, with the GIL held.
  void raise_if_failed() {
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  void send(const pipeline::StageEvent& e) {
    static constexpr const char* kinds[] = {"plan", "begin", "advance", "end"};
    const py::gil_scoped_acquire gil;
    if (error_) return;
    try {
      callback_(kinds[static_cast<int>(e.kind)], e.stage, e.stages, std::string(e.name), e.done, e.total,
                std::string(e.unit), e.seconds);
    } catch (py::error_already_set&) {
      error_ = std::current_exception();
    }
  }
  py::object callback_;
  std::exception_ptr error_;
};

// ---- map_sequence: the pipeline of `seqtopo map` -----------------------------------------------------

py::dict loop_closure_metrics(const evaluation::LoopClosureMetrics& m) {
  py::dict d;
  d["tp"] = m.tp;
  d["fp"] = m.fp;
  d["fn"] = m.fn;
  d["precision"] = m.precision;
  d["recall"] = m.recall;
  d["f1"] = m.f1;
  d["auc"] = m.auc;
  d["recall_at_100_precision"] = m.recall_at_100_precision;
  py::list curve;
  for (const auto& p : m.curve) curve.append(py::make_tuple(p.threshold, p.precision, p.recall));
  d["pr_curve"] = curve;
  return d;
}

// The preset's settings as the Python module shows them.
py::dict map_preset(const std::string& name) {
  const auto s = pipeline::map_preset(name);
  py::dict d;
  d["config"] = s.map;
  py::list descriptors;
  for (auto x : s.descriptors) descriptors.append(std::string(pipeline::descriptor_name(x)));
  d["descriptors"] = descriptors;
  d["metric"] = s.similarity.distance
                    ? py::object(py::str(std::string(similarity::distance_name(*s.similarity.distance))))
                    : py::object(py::none());
  return d;
}

// The descriptor options of `map` and `localize` as the library takes them: names (each may be a comma list), a
// metric name, kappa and threads.
pipeline::DescriptorOverrides described(const std::vector<std::string>& descriptors,
                                        const std::optional<std::string>& metric, std::optional<float> kappa,
                                        unsigned threads) {
  pipeline::DescriptorOverrides o;
  if (!descriptors.empty()) {
    o.descriptors.emplace();
    for (const auto& names : descriptors) {
      for (auto d : pipeline::parse_descriptors(names)) o.descriptors->push_back(d);
    }
  }
  if (metric) o.metric = similarity::parse_distance(*metric);
  check_kappa(kappa);
  o.kappa = kappa;
  o.threads = threads;
  return o;
}

// pipeline::map_sequence from the command line's inputs, through the request and the overrides the command line
// fills (map_request.hpp); the run stays a C++ object (MapRun) that Python reads and writes out.
pipeline::MapRun map_sequence(const std::vector<std::filesystem::path>& paths, const std::string& preset,
                              const mapping::MapConfig& config, const std::vector<std::string>& descriptors,
                              const std::optional<std::string>& metric, std::optional<float> kappa,
                              const std::string& input_kind, std::size_t every, unsigned threads,
                              const std::vector<std::filesystem::path>& odometry,
                              const std::filesystem::path& ground_truth, std::optional<double> gt_radius,
                              const std::filesystem::path& gt_places, const std::filesystem::path& gt_poses,
                              const std::string& engine, bool streaming, bool sparse,
                              std::optional<std::size_t> neighbours, std::optional<std::size_t> diagonal_reach,
                              const py::object& progress) {
  pipeline::MapRequest request;
  request.preset = preset;
  pipeline::MapSettings base = pipeline::map_preset(preset);
  base.map = config;  // the preset's, with the keyword overrides Python applied
  pipeline::MapOverrides set;
  set.described = described(descriptors, metric, kappa, threads);
  request.settings = pipeline::apply_overrides(std::move(base), set);
  try {
    request.engine = pipeline::engine_with_flags(pipeline::parse_engine(engine), streaming, sparse);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("engine: ") + e.what());
  }
  request.sparse.neighbours = neighbours;
  request.sparse.diagonal_reach = diagonal_reach;
  if (every == 0) throw std::invalid_argument("every must be >= 1");
  // Several paths are sessions, as `seqtopo map S1 S2 ...`; odometry none, or one file per session.
  if (!odometry.empty() && odometry.size() != paths.size()) {
    throw std::invalid_argument("odometry: " + std::to_string(odometry.size()) + " files for " +
                                std::to_string(paths.size()) + " sessions: give one per session, in their order");
  }
  for (std::size_t k = 0; k < paths.size(); ++k) {
    pipeline::SessionSource session;
    session.input = {paths[k], pipeline::parse_input_kind(input_kind), every};
    if (!odometry.empty()) session.odometry = odometry[k];
    request.sessions.push_back(std::move(session));
  }
  request.truth = {ground_truth, gt_radius, gt_places, gt_poses};
  PythonProgress reporter(progress);
  std::optional<pipeline::MapRun> run;
  {
    const py::gil_scoped_release release;
    run = pipeline::map_sequence(request, reporter.observer());
  }
  reporter.raise_if_failed();
  return std::move(*run);
}

// The whole map from arrays in memory (one N x N similarity per descriptor or sensor), with the truth as arrays:
// same_place N x N (non-zero = same place), true places per image (and the true junctions), true poses N x 3
// (with odometry N x 3, x y theta [m, m, rad]).
pipeline::MapRun map_similarities(const py::sequence& similarities, const std::vector<std::string>& names,
                                  const mapping::MapConfig& config, const py::object& odometry,
                                  const py::object& same_place, const std::vector<int>& true_places,
                                  const std::vector<int>& true_junctions, const py::object& true_poses,
                                  const py::object& progress) {
  std::vector<MatrixView> views;
  for (std::size_t k = 0; k < similarities.size(); ++k) views.push_back(matrix_view(similarities[k], "similarity"));
  const std::size_t n = views.empty() ? 0 : views.front().rows;
  // Truth or odometry of another length than the sequence would be read against the wrong images.
  const auto require_images = [n](std::size_t rows, const std::string& name, const char* what) {
    if (rows != n) {
      throw std::invalid_argument(name + ": " + std::to_string(rows) + " " + what + " for " + std::to_string(n) +
                                  " images");
    }
  };
  const auto poses_of = [&](const py::object& object, const char* name) {
    std::vector<Pose2> poses;
    if (object.is_none()) return poses;
    const MatrixView view = matrix_view(object, name);
    if (view.cols != 3) throw std::invalid_argument(std::string(name) + ": expected N x 3 (x, y, theta)");
    require_images(view.rows, name, "rows");
    require_finite(view, name);
    for (std::size_t i = 0; i < view.rows; ++i) {
      poses.push_back({view.data[3 * i], view.data[3 * i + 1], view.data[3 * i + 2]});
    }
    return poses;
  };
  const std::vector<Pose2> odo = poses_of(odometry, "odometry");
  pipeline::MapTruth truth;
  truth.poses = poses_of(true_poses, "gt_poses");
  if (!true_places.empty()) require_images(true_places.size(), "gt_places", "places");
  truth.places = true_places;
  truth.junctions = true_junctions;
  if (!same_place.is_none()) {
    const MatrixView view = matrix_view(same_place, "ground_truth");
    if (view.rows != view.cols) throw std::invalid_argument("ground_truth: expected an N x N matrix");
    require_images(view.rows, "ground_truth", "rows");
    require_finite(view, "ground_truth");
    auto matrix = std::make_shared<DenseMatrix<std::uint8_t>>(view.rows, view.cols, std::uint8_t{0});
    for (std::size_t k = 0; k < view.size(); ++k) matrix->values[k] = view.data[k] != 0 ? 1 : 0;
    truth.same_place = [matrix](std::size_t i, std::size_t j) {
      return i < matrix->rows && j < matrix->cols && (*matrix)(i, j) != 0;
    };
  }
  auto settings = pipeline::map_preset("default");
  settings.map = config;
  PythonProgress reporter(progress);
  std::optional<pipeline::MapRun> run;
  {
    const py::gil_scoped_release release;
    std::vector<SimilarityMatrix> matrices;
    for (const auto& view : views) {
      require_finite(view, "similarity");
      matrices.push_back(to_matrix(view));
    }
    run = pipeline::map_similarities(std::move(matrices), names, settings, odo, truth, reporter.observer());
  }
  reporter.raise_if_failed();
  return std::move(*run);
}

void write_map_outputs(const pipeline::MapRun& run, const std::filesystem::path& folder) {
  const py::gil_scoped_release release;
  io::OutputDirectory out(folder);
  outputs::write_map_outputs(run, out);
  outputs::write_map_report(run, out);
  out.commit();
}

// ---- localize_sequences: the pipeline of `seqtopo localize` ------------------------------------------

py::dict localization_metrics(const evaluation::LocalizationMetrics& m) {
  py::dict d;
  d["recall_at_1"] = m.recall_at_1;
  d["recall_at_5"] = m.recall_at_5;
  d["precision"] = m.precision;
  d["recall"] = m.recall;
  d["auc"] = m.auc;
  d["recall_at_100_precision"] = m.recall_at_100_precision;
  d["queries"] = m.queries;
  d["correct"] = m.correct;
  py::list curve;
  for (const auto& p : m.curve) curve.append(py::make_tuple(p.threshold, p.precision, p.recall));
  d["pr_curve"] = curve;
  return d;
}

pipeline::LocalizeRun localize_sequences(const std::filesystem::path& map, const std::filesystem::path& query,
                                         const std::string& descriptor, const std::optional<std::string>& metric,
                                         std::optional<float> kappa, const std::string& input_kind, std::size_t every,
                                         unsigned threads, const localize::LocalizeConfig& config, bool online,
                                         const std::string& ground_truth, std::optional<std::size_t> tolerance) {
  pipeline::LocalizeRequest request;
  const auto kind = pipeline::parse_input_kind(input_kind);
  if (every == 0) throw std::invalid_argument("every must be >= 1");
  request.map = {pipeline::SequenceInput(map, kind, every)};
  request.query = {query, kind, every};
  if (query.empty()) {
    request.similarity_file = map;  // one query x map similarity.npy
  }
  // An empty descriptor: the map's default, as the command without --descriptor.
  pipeline::apply_descriptor_overrides(
      described(descriptor.empty() ? std::vector<std::string>{} : std::vector<std::string>{descriptor}, metric, kappa,
                threads),
      request.settings.descriptors, request.settings.detect_panoramas, request.settings.similarity);
  request.settings.localize = config;
  request.online = online;
  std::optional<pipeline::GroundTruthFile> source;
  constexpr std::string_view keywords[] = {"same-index"};
  if (!ground_truth.empty()) source = pipeline::read_ground_truth(ground_truth, keywords, std::nullopt);
  const py::gil_scoped_release release;
  pipeline::LocalizeRun run = pipeline::localize_sequences(request);
  if (source) {
    const auto truth = pipeline::localization_truth(*source, run.queries, run.maps);
    // As the command: by the truth's format unless given (2 frames around same-index, a file's frames as listed).
    pipeline::evaluate_localization_run(
        run, truth, tolerance.value_or(pipeline::default_localization_tolerance(*source)), threads == 0 ? 2 : threads);
  }
  return run;
}

void write_localize_outputs(const pipeline::LocalizeRun& run, const std::filesystem::path& folder) {
  const py::gil_scoped_release release;
  io::OutputDirectory out(folder);
  outputs::write_localize_outputs(run, out);
  outputs::write_localize_report(run, out);
  out.commit();
}

void bind_localize_run(py::module_& m) {
  py::class_<pipeline::LocalizeRun>(m, "LocalizeRun")
      .def_readonly("online", &pipeline::LocalizeRun::online)
      .def_readonly("inputs", &pipeline::LocalizeRun::inputs)
      .def_readonly("queries", &pipeline::LocalizeRun::queries)
      .def_readonly("maps", &pipeline::LocalizeRun::maps)
      .def_readonly("timings", &pipeline::LocalizeRun::timings)
      .def_readonly("seconds", &pipeline::LocalizeRun::seconds)
      .def_readonly("tolerance", &pipeline::LocalizeRun::tolerance)
      .def_property_readonly("latencies",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<double> v = r.latencies;
                               return to_array(std::move(v));
                             })
      .def_property_readonly("waits",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<double> v = r.waits;
                               return to_array(std::move(v));
                             })
      .def_property_readonly("similarity",
                             [](const pipeline::LocalizeRun& r) {
                               SimilarityMatrix copy = r.similarity;
                               return to_array(std::move(copy));
                             })
      .def_property_readonly("map",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<Index> v;
                               for (const auto& a : r.answers) v.push_back(a.map ? index(*a.map) : -1);
                               return to_array(std::move(v));
                             })
      .def_property_readonly("score",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<float> v;
                               for (const auto& a : r.answers) v.push_back(a.score);
                               return to_array(std::move(v));
                             })
      .def_property_readonly("confidence",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<double> v;
                               for (const auto& a : r.answers) v.push_back(a.confidence);
                               return to_array(std::move(v));
                             })
      .def_property_readonly("in_map",
                             [](const pipeline::LocalizeRun& r) {
                               std::vector<bool> v;
                               for (const auto& a : r.answers) v.push_back(a.in_map);
                               return bool_array(v);
                             })
      .def_property_readonly("calibration",
                             [](const pipeline::LocalizeRun& r) {
                               if (!r.calibration) return py::object(py::none());
                               py::dict d;
                               d["ece"] = r.calibration->ece;
                               d["frames"] = r.calibration->detections;
                               return py::object(d);
                             })
      .def_property_readonly("alignments", [](const pipeline::LocalizeRun& r) { return alignments_list(r.alignments); })
      .def_property_readonly("metrics",
                             [](const pipeline::LocalizeRun& r) {
                               return r.metrics ? py::object(localization_metrics(*r.metrics)) : py::object(py::none());
                             })
      .def_property_readonly("baselines", [](const pipeline::LocalizeRun& r) {
        if (!r.single_frame || !r.seqslam) return py::object(py::none());
        py::dict d;
        d["single_frame"] = localization_metrics(*r.single_frame);
        d["seqslam"] = localization_metrics(*r.seqslam);
        return py::object(d);
      });
}

void bind_map_run(py::module_& m) {
  py::class_<pipeline::MapRun>(m, "MapRun")
      .def_property_readonly("result",
                             [](const pipeline::MapRun& r) {
                               mapping::MapResult copy = r.result;
                               return map_result(std::move(copy));
                             })
      .def_property_readonly("similarities",
                             [](const pipeline::MapRun& r) {
                               py::list out;
                               for (std::size_t k = 0; k < r.similarities.size(); ++k) {
                                 pipeline::SimilarityResult s = r.similarities[k];
                                 if (k < r.matrices.size()) s.similarity = r.matrices[k];
                                 out.append(similarity_result(std::move(s)));
                               }
                               return out;
                             })
      .def_readonly("descriptor_names", &pipeline::MapRun::descriptor_names)
      .def_property_readonly("sessions",
                             [](const pipeline::MapRun& r) {
                               py::list out;
                               for (const auto& s : r.map_sessions()) {
                                 py::dict d;
                                 d["input"] = s.input;
                                 d["begin"] = s.begin;
                                 d["end"] = s.end;
                                 if (s.gap > 0)
                                   d["break"] =
                                       py::dict(py::arg("gap") = s.gap, py::arg("median_interval") = s.median_interval);
                                 out.append(std::move(d));
                               }
                               return out;
                             })
      .def_readonly("input", &pipeline::MapRun::input)
      .def_readonly("preset", &pipeline::MapRun::preset)
      .def_property_readonly("engine",
                             [](const pipeline::MapRun& r) { return std::string(pipeline::engine_name(r.engine)); })
      .def_readonly("timings", &pipeline::MapRun::timings)
      .def_property_readonly("metrics",
                             [](const pipeline::MapRun& r) {
                               return r.metrics ? py::object(loop_closure_metrics(*r.metrics)) : py::object(py::none());
                             })
      .def_property_readonly("baseline",
                             [](const pipeline::MapRun& r) {
                               if (!r.baseline_metrics) return py::object(py::none());
                               py::dict d = loop_closure_metrics(*r.baseline_metrics);
                               d["method"] = r.baseline_name;
                               return py::object(d);
                             })
      .def_property_readonly("topology",
                             [](const pipeline::MapRun& r) {
                               if (!r.topology) return py::object(py::none());
                               const auto& t = *r.topology;
                               py::dict d;
                               d["adjusted_rand_index"] = t.adjusted_rand_index;
                               d["adjusted_rand_index_frames"] = t.adjusted_rand_index_frames;
                               d["false_merges"] = t.false_merges;
                               d["missed_merges"] = t.missed_merges;
                               d["junctions_true"] = t.junctions_true;
                               d["junctions_found"] = t.junctions_found;
                               d["junctions_matched"] = t.junctions_matched;
                               return py::object(d);
                             })
      .def_property_readonly("trajectory_errors", [](const pipeline::MapRun& r) {
        if (!r.ate) return py::object(py::none());
        py::dict d;
        d["odometry"] = r.ate->odometry;
        d["ekf"] = r.ate->ekf;
        d["pose_graph"] = r.ate->pose_graph;
        return py::object(d);
      });
}

// ---- match_strings -----------------------------------------------------------------------------------

py::list match_strings(const std::vector<std::string>& db, const std::vector<std::string>& queries,
                       const strings::MatchConfig& config, std::size_t window) {
  strings::validate(config.costs);
  std::vector<strings::QueryMatches> matches;
  {
    const py::gil_scoped_release release;
    matches = strings::match_all_windowed(db, queries, config, window);
  }
  py::list out;
  for (const auto& m : matches) {
    std::vector<Index> db_index, rank, rotation;
    std::vector<double> score;
    for (const auto& c : m.ranked) {
      db_index.push_back(index(c.db_index));
      score.push_back(c.score);
      rank.push_back(index(c.rank));
      rotation.push_back(index(c.rotation));
    }
    out.append(py::make_tuple(to_array(std::move(db_index)), to_array(std::move(score)), to_array(std::move(rank)),
                              to_array(std::move(rotation))));
  }
  return out;
}

void register_exceptions(py::module_& m) {
  // seqtopo.InputError: a problem with a file or option the user gave; str() is the CLI's
  // "<subject>: <message>", and .subject / .message hold the two parts.
  static PyObject* input_error = nullptr;
  const py::exception<InputError> type(m, "InputError", PyExc_ValueError);
  input_error = type.ptr();
  Py_INCREF(input_error);  // lives as long as the interpreter: the translator may run until then
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      const py::object cls = py::reinterpret_borrow<py::object>(input_error);
      py::object error = cls(e.subject() + ": " + e.what());
      error.attr("subject") = e.subject();
      error.attr("message") = std::string(e.what());
      PyErr_SetObject(input_error, error.ptr());
    } catch (const similarity::MemoryError& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    }
  });
}

}  // namespace
}  // namespace seqtopo::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace seqtopo::python;
  m.doc() = "Compiled core of seqtopo; use the seqtopo package, which documents and wraps these functions.";
  m.attr("__version__") = std::string(seqtopo::version());
  register_exceptions(m);
  bind_configs(m);
  bind_online(m);

  m.def("align", &align_scores, py::arg("scores"), py::arg("config"), py::arg("reverse"), py::arg("threads"));
  m.def("build_map", &build_map, py::arg("similarities"), py::arg("config"));
  bind_map_run(m);
  m.def("map_preset", &map_preset, py::arg("name"));
  m.def("map_sequence", &map_sequence, py::arg("paths"), py::arg("preset"), py::arg("config"), py::arg("descriptors"),
        py::arg("metric"), py::arg("kappa"), py::arg("input_kind"), py::arg("every"), py::arg("threads"),
        py::arg("odometry"), py::arg("ground_truth"), py::arg("gt_radius"), py::arg("gt_places"), py::arg("gt_poses"),
        py::arg("engine"), py::arg("streaming"), py::arg("sparse"), py::arg("neighbours"), py::arg("diagonal_reach"),
        py::arg("progress"));
  m.def("write_map_outputs", &write_map_outputs, py::arg("run"), py::arg("folder"));
  m.def("map_similarities", &map_similarities, py::arg("similarities"), py::arg("names"), py::arg("config"),
        py::arg("odometry"), py::arg("same_place"), py::arg("true_places"), py::arg("true_junctions"),
        py::arg("true_poses"), py::arg("progress"));
  bind_localize_run(m);
  m.def("localize_sequences", &localize_sequences, py::arg("map"), py::arg("query"), py::arg("descriptor"),
        py::arg("metric"), py::arg("kappa"), py::arg("input_kind"), py::arg("every"), py::arg("threads"),
        py::arg("config"), py::arg("online"), py::arg("ground_truth"), py::arg("tolerance"));
  m.def("write_localize_outputs", &write_localize_outputs, py::arg("run"), py::arg("folder"));
  m.def("localize", &localize, py::arg("similarity"), py::arg("config"));
  m.def("similarity_of_descriptors", &similarity_of_descriptors, py::arg("descriptors"), py::arg("against"),
        py::arg("metric"), py::arg("kappa"), py::arg("threads"), py::arg("kappa_rule"));
  m.def("similarity_of_path", &similarity_of_path, py::arg("path"), py::arg("against"), py::arg("descriptor"),
        py::arg("metric"), py::arg("kappa"), py::arg("input_kind"), py::arg("every"), py::arg("threads"),
        py::arg("kappa_rule"));
  m.def("match_strings", &match_strings, py::arg("db"), py::arg("queries"), py::arg("config"), py::arg("window"));
  m.def(
      "engine_input", [](const py::handle& array) { return matrix_view(array, "array").array; }, py::arg("array"),
      "The float32 C-order array the functions read for `array`: the array itself when it already is one "
      "(no copy), else a converted copy.");
}
