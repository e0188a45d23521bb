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
#include "seqtopo/similarity/distance.hpp"

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

void apply_overrides(mapping::OnlineMapConfig& c, const MapOverrides& o) {
  apply_section_overrides(c.score, c.search, c.significance, o);
  if (o.frames_per_place) {
    c.unit = align::Unit::places;
    c.frames_per_place = *o.frames_per_place;
  }
}

OnlineMapRun run_online_map(const OnlineMapRequest& request, const OnlineMapFrameCallback& on_frame) {
  const auto start = std::chrono::steady_clock::now();
  OnlineMapRun run;
  const SequenceInput& input = request.input;
  // The ground truth is read (its format recognized and parsed) before the first frame; its size is checked at the
  // end, when the number of frames is known.
  std::optional<GroundTruthFile> truth;
  if (!request.truth.same_place.empty())
    truth = read_ground_truth(request.truth.same_place.string(), {}, request.truth.radius);
  const bool from_stream = input.path == "-";
  run.kind = from_stream ? InputKind::images : resolve_input_kind(input);
  mapping::OnlineMapConfig config = request.config;
  const std::string subject = input.path.string();
  switch (run.kind) {
    case InputKind::bag:
      throw InputError(subject,
                       "--online reads image folders, videos, descriptors.npy, similarity.npy or image "
                       "paths on stdin (-), not bags");
    case InputKind::descriptors:
      config.distance = similarity::Distance::cosine;
      break;
    case InputKind::images:
    case InputKind::video:
      config.distance = similarity::Distance::sad;
      break;
    default:
      break;
  }
  // A matrix input is read whole; a similarity's own diagonal is S(t, t), which its rows below leave out (the place
  // scale needs it: mapping::OnlineMapConfig::self_similarity).
  std::optional<DenseMatrix<float>> matrix;
  if (run.kind == InputKind::descriptors || run.kind == InputKind::similarity) {
    if (run.kind == InputKind::similarity) refuse_every_for_similarity(input);
    matrix = read_input_rows(input);
    if (matrix->rows == 0 || matrix->cols == 0) throw InputError(subject, "holds no row");
    if (run.kind == InputKind::similarity) {
      if (matrix->rows != matrix->cols) {
        throw InputError(subject,
                         fmt::format("a similarity matrix must be square, got {} x {}", matrix->rows, matrix->cols));
      }
      std::vector<float> diagonal;  // finite values only (a non-finite one is refused with its row below)
      for (std::size_t t = 0; t < matrix->rows; ++t) {
        if (std::isfinite((*matrix)(t, t))) diagonal.push_back((*matrix)(t, t));
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
      return m.add_similarities(rows);
    });
  };
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
  } else if (run.kind == InputKind::images) {
    const ImageListing listing = list_input_images(input);
    for (const auto& file : listing.files) {
      const RgbImage image = image::load_image(file);
      run.image_files.push_back(file);
      add_image(image_name(input.path, file, input.recursive), image, file.string());
    }
  } else if (run.kind == InputKind::video) {
    const auto read =
        image::for_each_video_frame(input.path, input.every, [&](std::size_t index, const RgbImage& image) {
          add_image(fmt::format("frame {}", index), image, fmt::format("{}: frame {}", subject, index));
        });
    if (std::string warning = image::video_ended_early(input.path, read); !warning.empty()) {
      run.warnings.push_back(std::move(warning));
    }
  } else if (run.kind == InputKind::descriptors || run.kind == InputKind::similarity) {
    const DenseMatrix<float>& rows = *matrix;
    const bool similarity = run.kind == InputKind::similarity;
    for (std::size_t t = 0; t < rows.rows; ++t) {
      const auto row = rows.row(t);
      for (float v : row) {
        if (!std::isfinite(v)) throw InputError(subject, fmt::format("row {} has a non-finite value", t));
      }
      feeder.frame(fmt::format("row {}", t), [&](mapping::OnlineMapper& m) {
        return similarity ? m.add_similarity(row.first(t)) : m.add_descriptor(row);
      });
    }
  } else {
    throw InputError(subject, "unsupported input for --online");
  }
  if (run.frame_names.size() < 2) {
    throw InputError(from_stream ? "stdin" : subject,
                     fmt::format("needs at least 2 images, got {}", run.frame_names.size()));
  }
  feeder.finish();
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& e : run.events) ++run.event_counts[std::string(mapping::to_string(e.kind))];
  if (truth) {
    // Image paths from a stream are the frames as given (--every thins files, folders and videos).
    const auto same_place = same_place_truth(*truth, request.truth.radius, run.frames, from_stream ? 1 : input.every);
    const auto has_partner = evaluation::images_with_earlier_partner(
        run.frames, same_place.same_place, same_place.earlier_partners, config.search.min_separation);
    run.metrics =
        evaluation::evaluate_loop_closures(online_scored_pairs(run.loop_closures), has_partner, same_place.same_place);
  }
  if (request.offline_map) {
    MapRequest offline;
    offline.settings.similarity.threads = request.threads;
    offline.settings.map.threads = std::max(1U, request.threads);
    SessionSource session{input};
    if (from_stream) {
      // The files the stream named, in its order: the offline map reads the frames the online run read.
      session.input = SequenceInput("stdin", InputKind::images);
      session.input.listing = std::make_shared<const ImageListing>(ImageListing{run.image_files, {}});
    }
    offline.sessions = {std::move(session)};
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
