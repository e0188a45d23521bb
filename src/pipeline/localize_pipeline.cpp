#include "seqtopo/pipeline/localize_pipeline.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/stopwatch.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/localize/online_localizer.hpp"
#include "seqtopo/pipeline/baselines.hpp"
#include "seqtopo/similarity/distance.hpp"
#ifdef SEQTOPO_HAVE_RECORDING
#include "seqtopo/recording/recording.hpp"
#endif

namespace seqtopo::pipeline {
namespace {

using Clock = std::chrono::steady_clock;
FrameAnswer answer_of(const localize::FrameMatch& f) {
  FrameAnswer a;
  a.map = f.map;
  a.in_map = f.covered;
  a.score = f.score;
  a.confidence = f.confidence;
  a.e_value = f.e_value;
  a.candidates = f.candidates;
  return a;
}

std::vector<SequenceInput> map_inputs(const LocalizeRequest& request) {
  return request.map_sessions.empty() ? std::vector<SequenceInput>{request.map} : request.map_sessions;
}

// Frames of each map session, from the column names ("session/frame" when several).
std::vector<std::size_t> map_session_frames(const std::vector<SequenceInput>& maps,
                                            const std::vector<std::string>& columns) {
  if (maps.size() == 1) return {columns.size()};
  std::vector<std::size_t> frames;
  std::size_t k = 0;
  for (const auto& m : maps) {
    const std::string prefix = m.path.filename().string() + "/";
    std::size_t n = 0;
    while (k < columns.size() && columns[k].rfind(prefix, 0) == 0) {
      ++n;
      ++k;
    }
    frames.push_back(n);
  }
  return frames;
}

void run_offline(const LocalizeRequest& request, LocalizeRun& run) {
  const auto t0 = Clock::now();
  SimilarityResult s;
  try {
    if (request.similarity_file) {
      const SequenceInput file{*request.similarity_file, InputKind::similarity, 1};
      s = compute_similarity(file, file, request.settings.similarity);
    } else {
      const std::vector<SequenceInput> maps = map_inputs(request);
      s = compute_similarity(std::span<const SequenceInput>(&request.query, 1), maps, request.settings.similarity);
      run.map_session_frames = map_session_frames(maps, s.column_names);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(request.query.path.empty() ? request.map.path.string() : request.query.path.string(), e.what());
  }
  run.timings.emplace_back("similarity matrix", seconds_since(t0));
  run.similarity = std::move(s.similarity);
  run.queries = run.similarity.rows;
  run.maps = run.similarity.cols;

  const auto t1 = Clock::now();
  const auto result = localize::localize_sequence(run.similarity, request.settings.localize);
  run.timings.emplace_back("alignment (forward and reverse)", seconds_since(t1));
  for (std::size_t k = 0; k < result.alignments.size(); ++k) {
    const double e = result.e_values[k];
    if (std::isfinite(e) ? e <= 1.0 : result.alignments[k].score >= request.settings.localize.threshold) {
      run.alignments.push_back(result.alignments[k]);
      run.e_values.push_back(e);
    }
  }
  run.statistics = result.statistics;
  for (const auto& f : result.frames) run.answers.push_back(answer_of(f));
}

// A descriptor of one frame: dense (thumbnail, external descriptor) or a sparse joint histogram.
using FrameDescriptor = std::variant<std::vector<float>, similarity::SparseHistogram>;

struct Describer {
  Descriptor descriptor;
  SimilarityConfig config;
  std::string input;  // the input being read (named by an error of the image size)
  // The joint histogram does not resize: every image of the map and the query has the first one's size.
  std::optional<std::pair<int, int>> first_size;
  std::string first_input;

  FrameDescriptor operator()(const RgbImage& image) {
    if (descriptor == Descriptor::joint_histogram) {
      const std::pair size{image.width, image.height};
      if (!first_size) {
        first_size = size;
        first_input = input;
      } else if (size != *first_size) {
        const auto text = [](std::pair<int, int> p) {
          return std::to_string(p.first) + " x " + std::to_string(p.second);
        };
        throw InputError(
            input, (input == first_input ? "has images of " + text(size) + " and " + text(*first_size) + " pixels"
                                         : "its images are " + text(size) + " pixels, those of " + first_input + " " +
                                               text(*first_size)) +
                       ": the joint-histogram descriptor does not resize (its 3x3 and 5x5 windows "
                       "would see a different scale in each); give images of one size, or --descriptor "
                       "patch");
      }
      return image::joint_histogram(image, config.joint_histogram);
    }
    return dense_descriptor(image, descriptor, config);
  }
};

double frame_distance(similarity::Distance metric, const FrameDescriptor& a, const FrameDescriptor& b) {
  if (a.index() != b.index()) throw std::invalid_argument("both sequences must have the same kind of descriptor");
  if (const auto* x = std::get_if<std::vector<float>>(&a))
    return similarity::distance(metric, *x, std::get<std::vector<float>>(b));
  return similarity::distance(metric, std::get<similarity::SparseHistogram>(a),
                              std::get<similarity::SparseHistogram>(b));
}

// Calls visit(descriptor) for every frame of a sequence, in order, reading it lazily (a query folder is
// listed first; a query of "-" takes one image path at a time from next_path as the frames arrive).
// `arrival` (when given) is set to the time each frame arrives: its path read, before it is decoded.
void for_each_frame(const SequenceInput& input, Describer& describe, const NextPath& next_path,
                    const std::function<void(FrameDescriptor)>& visit, Clock::time_point* arrival = nullptr) {
  const auto arrived = [arrival] {
    if (arrival) *arrival = Clock::now();
  };
  if (input.path == "-") {
    if (!next_path) throw std::invalid_argument("a query of '-' needs a source of image paths");
    while (const auto line = next_path()) {
      if (line->empty()) continue;
      arrived();
      visit(describe(image::load_image(*line)));
    }
    return;
  }
  switch (resolve_input_kind(input)) {
    case InputKind::images:
      for (const auto& file : list_input_images(input).files) {
        arrived();
        visit(describe(image::load_image(file)));
      }
      return;
    case InputKind::video:
      image::for_each_video_frame(input.path, input.every, [&](std::size_t, const RgbImage& frame) {
        arrived();
        visit(describe(frame));
      });
      return;
    case InputKind::bag: {
#ifdef SEQTOPO_HAVE_RECORDING
      const recording::Recording bag(input.path);
      bag.for_each_image(bag.image_topic(input.image_topic), input.every, input.frames,
                         [&](std::size_t, double, const RgbImage& frame) { visit(describe(frame)); });
      return;
#else
      throw InputError(input.path.string(), "this seqtopo was built without bag support");
#endif
    }
    case InputKind::descriptors: {
      const auto rows = read_input_rows(input);
      if (rows.empty()) throw InputError(input.path.string(), "no descriptors (empty array)");
      for (std::size_t i = 0; i < rows.rows; ++i) {
        arrived();
        visit(std::vector<float>(rows.row(i).begin(), rows.row(i).end()));
      }
      return;
    }
    default:
      break;
  }
  throw InputError(input.path.string(), "expected an image folder, a video or descriptors.npy");
}

void run_online(const LocalizeRequest& request, const OnlineQueryCallback& on_frame, const NextPath& next_path,
                LocalizeRun& run) {
  const auto& config = request.settings.localize;
  auto report = [&](const localize::OnlineEstimate& e, double seconds, double wait) {
    FrameAnswer a;
    if (e.in_map) a.map = e.map;
    a.in_map = e.in_map;
    a.score = e.confidence;
    a.confidence = e.confidence;
    a.candidates = {e.map};
    run.answers.push_back(a);
    run.latencies.push_back(seconds);
    run.waits.push_back(wait);
    if (on_frame) on_frame(e.query, run.answers.back(), seconds, wait);
  };

  if (request.similarity_file) {
    // The rows of a precomputed matrix arrive one by one.
    const auto s = io::read_npy_matrix<float>(*request.similarity_file);
    if (s.empty()) throw InputError(request.similarity_file->string(), "empty similarity matrix");
    localize::OnlineLocalizer localizer(s.cols, config);
    for (std::size_t i = 0; i < s.rows; ++i) {
      const auto t = Clock::now();
      const auto e = localizer.feed(s.row(i));
      report(e, seconds_since(t), 0.0);
    }
    run.similarity = s;
    run.queries = s.rows;
    run.maps = s.cols;
    return;
  }

  // Image, video or descriptor inputs: the map is described once; each query frame then costs one
  // descriptor and one row of distances. The rows are contrast-enhanced, so S = 1 - kappa * D needs no kappa
  // (any kappa > 0 gives the same scores).
  const auto& sc = request.settings.similarity;
  const InputKind map_kind = resolve_input_kind(map_inputs(request).front());
  const Descriptor d = map_kind == InputKind::descriptors ? Descriptor::npy : sc.descriptor;
  if (d == Descriptor::npy && map_kind != InputKind::descriptors) {
    throw InputError("--descriptor", "npy needs descriptors .npy files as input");
  }
  const similarity::Distance metric = sc.distance.value_or(default_distance(d));
  Describer describe{d, sc, {}, std::nullopt, {}};
  const auto t0 = Clock::now();
  std::vector<FrameDescriptor> map;
  for (const auto& session : map_inputs(request)) {
    describe.input = session.path.string();
    const std::size_t before = map.size();
    for_each_frame(session, describe, next_path, [&](FrameDescriptor f) { map.push_back(std::move(f)); });
    run.map_session_frames.push_back(map.size() - before);
  }
  run.timings.emplace_back("map descriptors", seconds_since(t0));
  run.maps = map.size();
  localize::OnlineLocalizer localizer(map.size(), config);
  std::vector<float> row(map.size());
  std::vector<float> kept;
  // A frame's latency is its processing, from its arrival (its path read) to its answer: decoding, describing,
  // aligning. The time spent waiting for it since the previous answer is reported apart.
  auto arrival = Clock::now(), answered = arrival;
  describe.input = request.query.path == "-" ? std::string("stdin") : request.query.path.string();
  for_each_frame(
      request.query, describe, next_path,
      [&](FrameDescriptor q) {
        try {
          for (std::size_t j = 0; j < map.size(); ++j) row[j] = static_cast<float>(-frame_distance(metric, q, map[j]));
        } catch (const std::invalid_argument& e) {
          throw InputError(request.query.path.string(), e.what());
        }
        const auto e = localizer.feed(row);
        const auto now = Clock::now();
        kept.insert(kept.end(), row.begin(), row.end());
        report(e, std::chrono::duration<double>(now - arrival).count(),
               std::chrono::duration<double>(arrival - answered).count());
        // The wait for the next frame starts at this answer (before it is reported: whoever waits for the answer
        // to send the next frame never sees a wait shorter than its own pause).
        answered = now;
      },
      &arrival);
  run.queries = run.answers.size();
  if (run.queries == 0) throw InputError(request.query.path.string(), "no query frame");
  run.similarity = SimilarityMatrix(run.queries, run.maps, std::move(kept));
}

}  // namespace

LocalizeRun localize_sequences(const LocalizeRequest& request, const OnlineQueryCallback& on_frame,
                               const NextPath& next_query_path) {
  localize::validate(request.settings.localize);
  LocalizeRun run;
  run.online = request.online;
  run.settings = request.settings;
  std::string maps;
  for (const auto& m : map_inputs(request)) {
    if (!maps.empty()) maps += " + ";
    maps += m.path.string();
  }
  run.inputs =
      request.similarity_file ? request.similarity_file->string() : request.query.path.string() + " in " + maps;
  if (!request.similarity_file) {
    // Thumbnails of a map made of several sessions are not read (the report says so).
    if (request.map_sessions.size() <= 1) run.map_input = map_inputs(request).front();
    run.query_input = request.query;
  }
  const auto t0 = Clock::now();
  if (request.online) {
    run_online(request, on_frame, next_query_path, run);
  } else {
    run_offline(request, run);
  }
  run.seconds = seconds_since(t0);
  return run;
}

std::vector<evaluation::LocalizationPrediction> predictions(const std::vector<FrameAnswer>& answers) {
  std::vector<evaluation::LocalizationPrediction> p;
  for (const auto& a : answers) p.push_back({a.map, static_cast<float>(a.confidence), a.candidates});
  return p;
}

void evaluate_localization_run(LocalizeRun& run, const evaluation::LocalizationTruth& truth, std::size_t tolerance,
                               unsigned threads) {
  run.tolerance = tolerance;
  run.metrics = evaluation::evaluate_localization(predictions(run.answers), truth, tolerance);
  InMapDecision d;
  std::vector<double> confidence;
  std::vector<bool> correct;
  for (std::size_t q = 0; q < run.answers.size() && q < truth.truth.size(); ++q) {
    const auto& a = run.answers[q];
    const bool right = a.map && truth.correct(q, *a.map, tolerance);
    if (a.in_map) {
      ++d.in_map;
      d.correct += right ? 1 : 0;
    }
    confidence.push_back(a.confidence);
    correct.push_back(right);
  }
  d.precision = d.in_map == 0 ? 1.0 : static_cast<double>(d.correct) / static_cast<double>(d.in_map);
  d.recall = run.metrics->queries_with_match == 0
                 ? 0.0
                 : static_cast<double>(d.correct) / static_cast<double>(run.metrics->queries_with_match);
  run.decision = d;
  if (!run.online) run.calibration = evaluation::calibration(confidence, correct);
  run.single_frame = evaluation::evaluate_localization(single_frame_localization(run.similarity), truth, tolerance);
  const baseline::SeqSlamConfig seqslam = localization_seqslam_config(threads);
  run.seqslam = evaluation::evaluate_localization(seqslam_localization(run.similarity, seqslam), truth, tolerance);
  run.seqslam_method = fmt::format(
      "SeqSLAM (contrast window {}, sequence {}, velocities {}-{} in {} steps; frames with a whole sequence behind "
      "them answered)",
      seqslam.contrast_window, seqslam.sequence_length, seqslam.min_velocity, seqslam.max_velocity,
      seqslam.velocity_steps);
}

}  // namespace seqtopo::pipeline
