#include "seqtopo/pipeline/online_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <istream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/image/joint_histogram.hpp"
#include "seqtopo/image/patch_thumbnail.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/session_input.hpp"
#include "seqtopo/significance/low_information.hpp"
#include "seqtopo/similarity/distance.hpp"
#include "seqtopo/timeline/session_breaks.hpp"

namespace seqtopo::pipeline {
namespace {

namespace fs = std::filesystem;
using mapping::OnlineEvent;
using mapping::OnlineEventKind;

class Feeder {
 public:
  Feeder(const OnlineMapRequest& request, OnlineMapRun& run, const OnlineMapFrameCallback& on_frame)
      : run_(run), on_frame_(on_frame), mapper_(request.config) {}
  Feeder(mapping::OnlineMapConfig config, OnlineMapRun& run, const OnlineMapFrameCallback& on_frame)
      : run_(run), on_frame_(on_frame), mapper_(config) {}

  template <typename Add>
  void frame(std::string name, Add add) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<OnlineEvent> events = add(mapper_);
    run_.frame_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    run_.frame_names.push_back(std::move(name));
    deliver(std::move(events));
  }

  void finish() {
    deliver(mapper_.finish());
    run_.frames = mapper_.frames();
    run_.loop_closures = mapper_.loop_closures();
    run_.threshold = mapper_.threshold();
    run_.statistics = mapper_.statistics();
    run_.statistics_from_table = mapper_.statistics_from_table();
    run_.contrast_offset = mapper_.contrast_offset();
    run_.offset_changes = mapper_.offset_changes();
    run_.low_information_frames = mapper_.low_information_frames();
  }

 private:
  void deliver(std::vector<OnlineEvent> events) {
    if (on_frame_) on_frame_(mapper_.frames() == 0 ? 0 : mapper_.frames() - 1, events);
    run_.events.insert(run_.events.end(), std::make_move_iterator(events.begin()),
                       std::make_move_iterator(events.end()));
  }

  OnlineMapRun& run_;
  const OnlineMapFrameCallback& on_frame_;
  mapping::OnlineMapper mapper_;
};

}  // namespace

std::vector<std::vector<float>> OnlineImageRows::add(const RgbImage& image) {
  // The joint histogram does not resize: an image of another size would be compared at another scale (as offline,
  // sequence_similarity.cpp check_sizes).
  if (!histograms_.empty() && (image.width != width_ || image.height != height_)) {
    throw std::invalid_argument(fmt::format(
        "the image is {} x {} pixels, the first one {} x {}: the joint-histogram descriptor does not resize (its 3x3 "
        "and 5x5 windows would see a different scale in each); give images of one size",
        image.width, image.height, width_, height_));
  }
  width_ = image.width;
  height_ = image.height;
  last_low_information_ = low_information_.add(significance::grey_entropy(image));
  histograms_.push_back(image::joint_histogram(image, config_.joint_histogram));
  patches_.push_back(image::patch_thumbnail(image, config_.patch));
  const std::size_t t = histograms_.size() - 1;
  std::vector<std::vector<float>> rows(2, std::vector<float>(t));
  for (std::size_t j = 0; j < t; ++j) {
    rows[0][j] = -static_cast<float>(similarity::chi2_distance(histograms_[t], histograms_[j]));
    rows[1][j] = -static_cast<float>(similarity::sad_distance(patches_[t], patches_[j]));
  }
  return rows;
}

std::vector<OnlineEvent> OnlineImageRows::feed(mapping::OnlineMapper& mapper,
                                               const std::vector<std::vector<float>>& rows) const {
  if (last_low_information_) mapper.next_frame_low_information();
  return mapper.add_similarities(rows);
}

void apply_overrides(mapping::OnlineMapConfig& c, const MapOverrides& o) {
  apply_section_overrides(c.score, c.search, c.significance, o);
  if (o.frames_per_place) {
    c.unit = align::Unit::places;
    c.frames_per_place = *o.frames_per_place;
  }
}

namespace {

// What a session's frames are fed as: images (folders, videos, paths on a stream), descriptor rows, or similarity
// rows. Sessions of one run are fed alike.
enum class FeedKind { images, descriptors, similarity };

FeedKind feed_kind(InputKind kind, const std::string& subject) {
  switch (kind) {
    case InputKind::images:
    case InputKind::video:
      return FeedKind::images;
    case InputKind::descriptors:
      return FeedKind::descriptors;
    case InputKind::similarity:
      return FeedKind::similarity;
    case InputKind::bag:
      throw InputError(subject,
                       "--online reads image folders, videos, descriptors.npy, similarity.npy or image "
                       "paths on stdin (-), not bags");
    default:
      throw InputError(subject, "unsupported input for --online");
  }
}

}  // namespace

OnlineMapRun run_online_map(const OnlineMapRequest& request, const OnlineMapFrameCallback& on_frame) {
  const auto start = std::chrono::steady_clock::now();
  OnlineMapRun run;
  if (request.sessions.empty()) throw InputError("--online", "no input given");
  const bool from_stream = request.sessions.front().path == "-";
  if (request.sessions.size() > 1) {
    for (const auto& session : request.sessions) {
      if (session.path == "-") throw InputError("-", "image paths on stdin are one input alone, not a session");
    }
  }
  // The ground truth is read (its format recognized and parsed) before the first frame; its size is checked at the
  // end, when the number of frames is known.
  std::optional<GroundTruthFile> truth;
  if (!request.truth.same_place.empty())
    truth = read_ground_truth(request.truth.same_place.string(), {}, request.truth.radius);
  // Every session's kind before the first frame: sessions are fed alike (images, descriptor rows, or one
  // similarity).
  std::vector<InputKind> kinds;
  for (const auto& session : request.sessions)
    kinds.push_back(from_stream ? InputKind::images : resolve_input_kind(session));
  const FeedKind feed = feed_kind(kinds.front(), request.sessions.front().path.string());
  for (std::size_t k = 1; k < kinds.size(); ++k) {
    const std::string subject = request.sessions[k].path.string();
    if (feed_kind(kinds[k], subject) != feed) {
      throw InputError(subject, fmt::format("is {}, the first session {}: the sessions of one online map are of one "
                                            "kind (images and videos, or descriptors.npy)",
                                            input_kind_name(kinds[k]), input_kind_name(kinds.front())));
    }
    if (feed == FeedKind::similarity) {
      throw InputError(subject, "a similarity.npy is one session alone (its rows compare its own frames only)");
    }
  }
  run.kind = kinds.front();
  mapping::OnlineMapConfig config = request.config;
  if (feed == FeedKind::descriptors) config.distance = similarity::Distance::cosine;
  if (feed == FeedKind::images) config.distance = similarity::Distance::sad;
  // A matrix input is read whole; a similarity's own diagonal is S(t, t), which its rows below leave out (the place
  // scale needs it: mapping::OnlineMapConfig::self_similarity).
  std::vector<DenseMatrix<float>> matrices;
  if (feed != FeedKind::images) {
    for (const auto& session : request.sessions) {
      const std::string subject = session.path.string();
      if (feed == FeedKind::similarity) refuse_every_for_similarity(session);
      DenseMatrix<float> matrix = read_input_rows(session);
      if (matrix.rows == 0 || matrix.cols == 0) throw InputError(subject, "holds no row");
      if (!matrices.empty() && matrix.cols != matrices.front().cols) {
        throw InputError(subject,
                         fmt::format("has {} dimensions, the first session {}", matrix.cols, matrices.front().cols));
      }
      matrices.push_back(std::move(matrix));
    }
    if (feed == FeedKind::similarity) {
      const DenseMatrix<float>& m = matrices.front();
      if (m.rows != m.cols) {
        throw InputError(request.sessions.front().path.string(),
                         fmt::format("a similarity matrix must be square, got {} x {}", m.rows, m.cols));
      }
      std::vector<float> diagonal;  // finite values only (a non-finite one is refused with its row below)
      for (std::size_t t = 0; t < m.rows; ++t) {
        if (std::isfinite(m(t, t))) diagonal.push_back(m(t, t));
      }
      if (!diagonal.empty()) {
        const auto middle = diagonal.begin() + static_cast<std::ptrdiff_t>(diagonal.size() / 2);
        std::nth_element(diagonal.begin(), middle, diagonal.end());
        config.self_similarity = *middle;
      }
    }
  }
  Feeder feeder(config, run, on_frame);
  OnlineImageRows image_rows(request.similarity);
  // Session breaks inside an image folder with times (timeline/session_breaks.hpp), as the frames arrive.
  timeline::OnlineBreakFinder breaks;
  std::vector<double> session_times;  // the current session's frame times, or empty
  std::size_t session_begin = 0;      // its first frame
  // `where`: the file, or the video and the frame, named by an error of the image's size.
  auto add_image = [&](std::string name, const RgbImage& image, const std::string& where) {
    // The descriptors are the frame's own work too: they are timed with it.
    feeder.frame(std::move(name), [&](mapping::OnlineMapper& m) {
      std::vector<std::vector<float>> rows;
      try {
        rows = image_rows.add(image);
      } catch (const std::invalid_argument& e) {
        throw InputError(where, e.what());
      }
      const std::size_t t = m.frames();
      const std::size_t k = t - session_begin;
      const auto gap =
          breaks.add(k < session_times.size() ? std::optional<double>(session_times[k]) : std::nullopt, rows);
      std::vector<OnlineEvent> events = image_rows.feed(m, rows);
      if (gap && gap->session_break) {
        OnlineEvent e;
        e.kind = mapping::OnlineEventKind::session_break;
        e.frame = t;
        e.i = t;
        e.j = t - 1;
        e.gap = gap->gap.gap;
        e.median_interval = gap->gap.median_interval;
        events.insert(events.begin(), e);
      }
      return events;
    });
  };
  for (std::size_t k = 0; k < request.sessions.size(); ++k) {
    const SequenceInput& input = request.sessions[k];
    const std::string subject = input.path.string();
    const std::size_t begin = run.frame_names.size();
    breaks.start_session();
    session_begin = begin;
    session_times.clear();
    // An image folder is listed once: its frames, and their times where its names or a times.txt give them.
    SequenceInput listed = input;
    if (!from_stream && kinds[k] == InputKind::images) {
      listed.listing = std::make_shared<const ImageListing>(list_input_images(input));
      try {  // only to find session breaks: names that are not times (or not increasing ones) give none
        if (auto t = frame_times(listed, {})) session_times = std::move(*t);
        timeline::time_gaps(session_times);  // throws on times that are not a recording's own
      } catch (const InputError&) {
        session_times.clear();
      } catch (const std::invalid_argument&) {
        session_times.clear();
      }
    }
    if (from_stream) {
      if (request.paths == nullptr) throw std::invalid_argument("run_online_map: input '-' needs a stream of paths");
      // Bounded lines: binary data on stdin (/dev/zero) is an error, not a line that grows without end.
      while (const auto line = read_bounded_line(*request.paths, "stdin")) {
        if (line->empty()) continue;
        const fs::path file(*line);
        const RgbImage image = image::load_image(file);  // InputError naming the file
        run.image_files.push_back(file);
        add_image(file.filename().string(), image, file.string());
      }
      if (run.frame_names.empty()) throw InputError("stdin", "no image path was given (one path per line)");
    } else if (kinds[k] == InputKind::images) {
      for (const auto& file : listed.listing->files) {
        const RgbImage image = image::load_image(file);
        run.image_files.push_back(file);
        add_image(image_name(input.path, file, input.recursive), image, file.string());
      }
    } else if (kinds[k] == InputKind::video) {
      const auto read =
          image::for_each_video_frame(input.path, input.every, [&](std::size_t index, const RgbImage& image) {
            add_image(fmt::format("frame {}", index), image, fmt::format("{}: frame {}", subject, index));
          });
      if (std::string warning = image::video_ended_early(input.path, read); !warning.empty()) {
        run.warnings.push_back(std::move(warning));
      }
    } else {
      const DenseMatrix<float>& rows = matrices[k];
      const bool similarity = feed == FeedKind::similarity;
      for (std::size_t t = 0; t < rows.rows; ++t) {
        const auto row = rows.row(t);
        for (float v : row) {
          if (!std::isfinite(v)) throw InputError(subject, fmt::format("row {} has a non-finite value", t));
        }
        feeder.frame(fmt::format("row {}", t), [&](mapping::OnlineMapper& m) {
          return similarity ? m.add_similarity(row.first(t)) : m.add_descriptor(row);
        });
      }
    }
    run.sessions.push_back({from_stream ? "stdin" : subject, begin, run.frame_names.size()});
  }
  if (run.frame_names.size() < 2) {
    throw InputError(from_stream ? "stdin" : request.sessions.front().path.string(),
                     fmt::format("needs at least 2 images, got {}", run.frame_names.size()));
  }
  feeder.finish();
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& e : run.events) ++run.event_counts[std::string(mapping::to_string(e.kind))];
  if (truth) {
    // Image paths from a stream are the frames as given (--every thins files, folders and videos).
    const auto same_place =
        same_place_truth(*truth, request.truth.radius, run.frames, from_stream ? 1 : request.sessions.front().every);
    const auto has_partner = evaluation::images_with_earlier_partner(
        run.frames, same_place.same_place, same_place.earlier_partners, config.search.min_separation);
    run.metrics =
        evaluation::evaluate_loop_closures(online_scored_pairs(run.loop_closures), has_partner, same_place.same_place);
  }
  if (request.offline_map) {
    MapRequest offline;
    offline.settings.similarity.threads = request.threads;
    offline.settings.map.threads = std::max(1U, request.threads);
    for (const auto& input : request.sessions) {
      SessionSource session{input};
      if (from_stream) {
        // The files the stream named, in its order: the offline map reads the frames the online run read.
        session.input = SequenceInput("stdin", InputKind::images);
        session.input.listing = std::make_shared<const ImageListing>(ImageListing{run.image_files, {}});
      }
      offline.sessions.push_back(std::move(session));
    }
    offline.truth.same_place = request.truth.same_place;
    offline.truth.radius = request.truth.radius;
    run.offline = MapJob(std::move(offline)).run();
  }
  return run;
}

std::vector<evaluation::ScoredPair> online_scored_pairs(const std::vector<mapping::OnlineLoopClosure>& closures) {
  std::vector<evaluation::ScoredPair> out;
  out.reserve(closures.size());
  for (const auto& c : closures) out.push_back({c.i, c.j, c.confidence});
  return out;
}

}  // namespace seqtopo::pipeline
