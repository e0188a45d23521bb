#include "seqtopo/pipeline/localize_pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
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
#include "seqtopo/pipeline/presets.hpp"
#include "seqtopo/significance/low_information.hpp"
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

// The descriptors the run uses (into run.settings, with a note when panoramas change them): the rows of a
// descriptors.npy map, else the settings', the panorama signature for 360-degree images.
void choose_descriptors(const LocalizeRequest& request, LocalizeRun& run) {
  auto& ds = run.settings.descriptors;
  if (ds.empty()) throw std::invalid_argument("no descriptor asked for");
  if (request.similarity_file) return;
  const SequenceInput& first = request.map.front();
  if (resolve_input_kind(first) == InputKind::descriptors) {
    ds = {Descriptor::npy};
    return;
  }
  if (std::find(ds.begin(), ds.end(), Descriptor::npy) != ds.end()) {
    throw InputError("--descriptor", "npy needs descriptors .npy files as input");
  }
  if (request.settings.detect_panoramas) {
    const std::string note = detect_panorama_descriptors(first, ds);
    if (!note.empty()) run.notes.push_back(note);
  }
}

void run_offline(const LocalizeRequest& request, LocalizeRun& run) {
  const auto t0 = Clock::now();
  std::vector<SimilarityResult> s;
  try {
    if (request.similarity_file) {
      const SequenceInput file{*request.similarity_file, InputKind::similarity, 1};
      s.push_back(compute_similarity(file, file, request.settings.similarity));
    } else {
      const std::vector<SequenceInput>& maps = request.map;
      s = compute_similarities(std::span<const SequenceInput>(&request.query, 1), maps, run.settings.descriptors,
                               request.settings.similarity);
      run.map_session_frames = map_session_frames(maps, s.front().column_names);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(request.query.path.empty() && !request.map.empty() ? request.map.front().path.string()
                                                                        : request.query.path.string(),
                     e.what());
  }
  run.timings.emplace_back("similarity matrix", seconds_since(t0));
  // Dark or near-uniform images carry no evidence of place, in the query or the map (each by its own median).
  localize::LowInformationFrames low_information;
  if (!s.empty()) {
    low_information.query = significance::low_information_frames(s.front().frame_entropy);
    low_information.map = significance::low_information_frames(s.front().column_entropy);
    if (!low_information.query.empty() || !low_information.map.empty()) {
      run.notes.push_back(fmt::format(
          "{} query and {} map images of little information (dark or near-uniform): no evidence of where the "
          "query is (soft-masked); such a query frame is placed by the evidence around it",
          low_information.query.size(), low_information.map.size()));
    }
  }
  std::vector<SimilarityMatrix> similarities;
  for (auto& r : s) similarities.push_back(std::move(r.similarity));

  const auto t1 = Clock::now();
  const auto& config = request.settings.localize;
  auto result = localize::localize_sequence(similarities, config, low_information);
  run.timings.emplace_back("alignment (forward and reverse)", seconds_since(t1));
  run.blind_descriptors = result.blind_descriptors;
  run.descriptor_weights = result.descriptor_weights;
  if (similarities.size() == 1) {
    run.similarity = std::move(similarities.front());
  } else {
    std::string weights;
    for (std::size_t d = 0; d < similarities.size(); ++d) {
      weights += fmt::format("{}{} {:.2f}", d == 0 ? "" : ", ", descriptor_name(run.settings.descriptors[d]),
                             result.descriptor_weights[d]);
    }
    run.notes.push_back("descriptors fused with the weights of their evidence: " + weights);
    for (std::size_t d : result.blind_descriptors) {
      run.notes.push_back(
          fmt::format("descriptor {} sees no revisit (none on its own, nor higher scores than chance "
                      "on the pairs another localizes): left out of the fusion",
                      descriptor_name(run.settings.descriptors[d])));
    }
    // What the figure and the baselines see: the fused enhanced scores, before the offset (and, for the baselines,
    // each descriptor's own similarity).
    run.similarity = std::move(result.fused_enhanced);
    for (std::size_t d = 0; d < similarities.size(); ++d) {
      run.descriptor_similarities.emplace_back(descriptor_name(run.settings.descriptors[d]),
                                               std::move(similarities[d]));
    }
  }
  run.queries = run.similarity.rows;
  run.maps = run.similarity.cols;
  for (std::size_t k = 0; k < result.alignments.size(); ++k) {
    const double e = result.e_values[k];
    if (std::isfinite(e) ? e <= 1.0 : result.alignments[k].score >= config.significance.threshold) {
      run.alignments.push_back(result.alignments[k]);
      run.e_values.push_back(e);
    }
  }
  run.statistics = result.statistics;
  for (const auto& f : result.frames) run.answers.push_back(answer_of(f));
}

// A descriptor of one frame: dense (thumbnail, external descriptor) or a sparse joint histogram.
using FrameDescriptor = std::variant<std::vector<float>, similarity::SparseHistogram>;

// One frame's descriptor per descriptor asked for.
struct Describer {
  std::vector<Descriptor> descriptors;
  SimilarityConfig config;
  std::string input;  // the input being read (named by an error of the image size)
  // The joint histogram does not resize: every image of the map and the query has the first one's size.
  std::optional<std::pair<int, int>> first_size;
  std::string first_input;

  std::vector<double> entropy;  // of each image described, in order (significance/low_information.hpp)

  std::vector<FrameDescriptor> operator()(const RgbImage& image) {
    entropy.push_back(significance::grey_entropy(image));
    std::vector<FrameDescriptor> out;
    for (Descriptor d : descriptors) out.push_back(describe(image, d));
    return out;
  }

  FrameDescriptor describe(const RgbImage& image, Descriptor descriptor) {
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
                    const std::function<void(std::vector<FrameDescriptor>)>& visit,
                    Clock::time_point* arrival = nullptr) {
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
        visit({std::vector<float>(rows.row(i).begin(), rows.row(i).end())});
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
    a.map = e.map;
    a.in_map = e.in_map;
    a.score = e.score;
    a.confidence = e.confidence;
    a.e_value = e.e_value;
    a.candidates = {e.map};
    run.answers.push_back(a);
    run.latencies.push_back(seconds);
    run.waits.push_back(wait);
    if (on_frame) on_frame(e.query, run.answers.back(), seconds, wait);
  };
  // With a lag (fixed-lag smoothing), each feed answers the frame `lag` frames back, its latency the feed's and the
  // smoothing's; the last ones are answered when the query ends, each with the smoothing's time and no wait.
  const auto answer = [&](const localize::OnlineLocalizer& localizer, const localize::OnlineEstimate& now,
                          double seconds, double wait) {
    if (config.lag == 0) return report(now, seconds, wait);
    if (now.query < config.lag) return;
    const auto t = Clock::now();
    const localize::OnlineEstimate late = localizer.smoothed(now.query - config.lag);
    report(late, seconds + seconds_since(t), wait);
  };
  const auto answer_the_rest = [&](const localize::OnlineLocalizer& localizer) {
    for (std::size_t q = run.answers.size(); q < localizer.frames_seen(); ++q) {
      const auto t = Clock::now();
      const localize::OnlineEstimate late = localizer.smoothed(q);
      report(late, seconds_since(t), 0.0);
    }
  };

  if (request.similarity_file) {
    // The rows of a precomputed matrix arrive one by one.
    const auto s = io::read_npy_matrix<float>(*request.similarity_file);
    if (s.empty()) throw InputError(request.similarity_file->string(), "empty similarity matrix");
    localize::OnlineLocalizer localizer(s.cols, config);
    for (std::size_t i = 0; i < s.rows; ++i) {
      const auto t = Clock::now();
      const auto e = localizer.feed(s.row(i));
      answer(localizer, e, seconds_since(t), 0.0);
    }
    answer_the_rest(localizer);
    run.similarity = s;
    run.queries = s.rows;
    run.maps = s.cols;
    return;
  }

  // Image, video or descriptor inputs: the map is described once; each query frame then costs its descriptors and
  // one row of distances for each. The rows are contrast-enhanced, so S = 1 - kappa * D needs no kappa (any
  // kappa > 0 gives the same scores); several descriptors' enhanced rows are fused as offline.
  const auto& sc = request.settings.similarity;
  const std::vector<Descriptor>& ds = run.settings.descriptors;
  std::vector<similarity::Distance> metrics;
  for (Descriptor d : ds) metrics.push_back(sc.distance.value_or(default_distance(d)));
  Describer describe{ds, sc, {}, std::nullopt, {}, {}};
  const auto t0 = Clock::now();
  std::vector<std::vector<FrameDescriptor>> map;
  for (const auto& session : request.map) {
    describe.input = session.path.string();
    const std::size_t before = map.size();
    for_each_frame(session, describe, next_path, [&](std::vector<FrameDescriptor> f) { map.push_back(std::move(f)); });
    run.map_session_frames.push_back(map.size() - before);
  }
  run.timings.emplace_back("map descriptors", seconds_since(t0));
  run.maps = map.size();
  localize::OnlineLocalizer localizer(map.size(), config, ds.size());
  // Images of little information, as offline: the map's by its own median, each query frame's as it arrives.
  const bool images = describe.entropy.size() == map.size();
  if (images) localizer.set_low_information_map(significance::low_information_frames(describe.entropy));
  describe.entropy.clear();
  significance::LowInformationStream query_low_information;
  const std::size_t m = map.size();
  std::vector<float> rows(ds.size() * m);
  std::vector<std::span<const float>> row_of;
  for (std::size_t d = 0; d < ds.size(); ++d) row_of.emplace_back(rows.data() + d * m, m);
  std::vector<std::vector<float>> kept(ds.size());
  // A frame's latency is its processing, from its arrival (its path read) to its answer: decoding, describing,
  // aligning. The time spent waiting for it since the previous answer is reported apart.
  auto arrival = Clock::now(), answered = arrival;
  describe.input = request.query.path == "-" ? std::string("stdin") : request.query.path.string();
  for_each_frame(
      request.query, describe, next_path,
      [&](std::vector<FrameDescriptor> q) {
        try {
          for (std::size_t d = 0; d < ds.size(); ++d) {
            float* row = rows.data() + d * m;
            for (std::size_t j = 0; j < m; ++j)
              row[j] = static_cast<float>(-frame_distance(metrics[d], q[d], map[j][d]));
          }
        } catch (const std::invalid_argument& e) {
          throw InputError(request.query.path.string(), e.what());
        }
        const bool dark = images && !describe.entropy.empty() && query_low_information.add(describe.entropy.back());
        const auto e = localizer.feed_descriptors(row_of, dark);
        const auto now = Clock::now();
        for (std::size_t d = 0; d < ds.size(); ++d) kept[d].insert(kept[d].end(), row_of[d].begin(), row_of[d].end());
        answer(localizer, e, std::chrono::duration<double>(now - arrival).count(),
               std::chrono::duration<double>(arrival - answered).count());
        // The wait for the next frame starts at this answer (before it is reported: whoever waits for the answer
        // to send the next frame never sees a wait shorter than its own pause).
        answered = now;
      },
      &arrival);
  answer_the_rest(localizer);
  run.queries = run.answers.size();
  if (run.queries == 0) throw InputError(request.query.path.string(), "no query frame");
  std::vector<SimilarityMatrix> seen;
  for (auto& k : kept) seen.emplace_back(run.queries, run.maps, std::move(k));
  if (seen.size() == 1) {
    run.similarity = std::move(seen.front());
  } else {
    // As offline: the fused enhanced scores before the offset, with the weights the localizer ended with.
    localize::LocalizeConfig unshifted = config;
    unshifted.score.contrast_offset = 0;
    run.descriptor_weights = localizer.weights();
    run.similarity = localize::fused_score_matrix(seen, unshifted, run.descriptor_weights);
  }
}

}  // namespace

LocalizeRun localize_sequences(const LocalizeRequest& request, const OnlineQueryCallback& on_frame,
                               const NextPath& next_query_path) {
  localize::validate(request.settings.localize);
  if (request.map.empty() && !request.similarity_file) throw std::invalid_argument("localize: no map given");
  LocalizeRun run;
  run.online = request.online;
  run.settings = request.settings;
  std::string maps;
  for (const auto& m : request.map) {
    if (!maps.empty()) maps += " + ";
    maps += m.path.string();
  }
  run.inputs =
      request.similarity_file ? request.similarity_file->string() : request.query.path.string() + " in " + maps;
  if (!request.similarity_file) {
    // Thumbnails of a map made of several sessions are not read (the report says so).
    if (request.map.size() == 1) run.map_input = request.map.front();
    run.query_input = request.query;
  }
  choose_descriptors(request, run);
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
  run.calibration = evaluation::calibration(confidence, correct);
  // Each baseline on every matrix of the run; the one that suits it best is reported.
  std::vector<std::pair<std::string, const SimilarityMatrix*>> sources{
      {run.descriptor_similarities.empty() ? std::string() : std::string("the fused enhanced scores"),
       &run.similarity}};
  for (const auto& [name, matrix] : run.descriptor_similarities) sources.emplace_back(name, &matrix);
  const auto better = [](const evaluation::LocalizationMetrics& a, const evaluation::LocalizationMetrics& b) {
    return a.recall_at_1 != b.recall_at_1 ? a.recall_at_1 > b.recall_at_1 : a.auc > b.auc;
  };
  const baseline::SeqSlamConfig seqslam = localization_seqslam_config(threads);
  std::string seqslam_source;
  run.single_frame.reset();
  run.seqslam.reset();
  for (const auto& [name, matrix] : sources) {
    auto single = evaluation::evaluate_localization(single_frame_localization(*matrix), truth, tolerance);
    if (!run.single_frame || better(single, *run.single_frame)) run.single_frame = std::move(single);
    auto sequence = evaluation::evaluate_localization(seqslam_localization(*matrix, seqslam), truth, tolerance);
    if (!run.seqslam || better(sequence, *run.seqslam)) {
      run.seqslam = std::move(sequence);
      seqslam_source = name;
    }
  }
  run.seqslam_method = fmt::format(
      "SeqSLAM (contrast window {}, sequence {}, velocities {}-{} in {} steps; frames with a whole sequence behind "
      "them answered){}",
      seqslam.contrast_window, seqslam.sequence_length, seqslam.min_velocity, seqslam.max_velocity,
      seqslam.velocity_steps, seqslam_source.empty() ? std::string() : " on " + seqslam_source);
}

}  // namespace seqtopo::pipeline
