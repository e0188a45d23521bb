#pragma once
// `seqtopo map INPUT --online`: the frames of a sequence fed one at a time, in order, to the online mapper
// (mapping/online_mapper.hpp), with the events of every frame handed to the caller before the next frame is read
// (docs/online.md).
//
// Frames: an image folder or a video (the offline default's two descriptors, joint histograms by chi2 and patch
// thumbnails by SAD, each row contrast-enhanced on its own and fused: OnlineImageRows), the rows of a
// descriptors.npy (cosine), image paths one per line on a stream (INPUT "-"), or the rows of a similarity.npy
// (row t's first t values: the similarity of frame t to the earlier frames).
//
// The job: the online run, its loop closures scored against a same-place ground truth when one is given, and, when
// asked, the offline map of the same frames (map_pipeline.hpp) scored alike, for the files outputs writes
// (outputs/online_outputs.hpp). The command line parses options, prints the events as they come and the summary.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "seqtopo/evaluation/loop_closure_metrics.hpp"
#include "seqtopo/formats/map_json.hpp"
#include "seqtopo/mapping/online_mapper.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"
#include "seqtopo/pipeline/map_request.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/significance/low_information.hpp"

namespace seqtopo::pipeline {

// The similarity rows of each new image to the images before it, for OnlineMapper::add_similarities: -chi2 of the
// joint histograms and -SAD of the patch thumbnails (S = 1 - kappa D up to kappa, which the contrast enhancement
// removes). Keeps every image's two descriptors. Every image has the first one's size (the joint histogram does not
// resize): another size is an std::invalid_argument.
class OnlineImageRows {
 public:
  explicit OnlineImageRows(const SimilarityConfig& config = {}) : config_(config) {}
  std::vector<std::vector<float>> add(const RgbImage& image);
  // The rows of the image added last given to `mapper`, told first when that image is of little information (dark
  // or near-uniform, significance::LowInformationStream: the offline rule as the images arrive); its events.
  std::vector<mapping::OnlineEvent> feed(mapping::OnlineMapper& mapper,
                                         const std::vector<std::vector<float>>& rows) const;

 private:
  SimilarityConfig config_;
  significance::LowInformationStream low_information_;
  bool last_low_information_ = false;
  int width_ = 0, height_ = 0;  // the first image's
  std::vector<similarity::SparseHistogram> histograms_;
  std::vector<std::vector<float>> patches_;
};

struct OnlineMapRequest {
  // The inputs, fed one after the other as the sessions of one map (one input is a list of one), all images and
  // videos, or all descriptors.npy of one width; a similarity.npy or "-" (image paths read from `paths`) alone.
  std::vector<SequenceInput> sessions;
  std::istream* paths = nullptr;    // for "-"
  mapping::OnlineMapConfig config;  // `distance` is set from the input (sad for images, cosine for npy rows)
  SimilarityConfig similarity;      // the patch thumbnail's settings
  // A same-place ground truth (`same_place` and `radius` only; ground_truth.hpp's formats but same-index) that the
  // loop closures standing at the end are scored against, as the offline map's; read before the first frame.
  MapTruthFiles truth;
  // Then the offline map of the same frames (the default preset; image paths from a stream are mapped as the
  // list of files they name), scored against the same truth.
  bool offline_map = false;
  unsigned threads = 0;  // the offline map's (0 = every core)
};

struct OnlineMapRun {
  InputKind kind = InputKind::automatic;
  std::vector<std::string> frame_names;
  std::vector<formats::MapSession> sessions;              // each input's frames [begin, end), in order
  std::vector<std::filesystem::path> image_files;         // images read (folder or stream), in order
  std::vector<mapping::OnlineEvent> events;               // every event, in order, finish() included
  std::vector<mapping::OnlineLoopClosure> loop_closures;  // standing at the end
  std::vector<double> frame_seconds;                      // the mapper's work per frame (not the reading and decoding)
  std::size_t frames = 0;
  // The significance after the last frame: the threshold a revisit needed and the statistics it came from
  // (invalid when none could be fitted, or with max_e_value unset), fitted to the islands or, while they were too
  // few, to the declumped alignments of the table so far (statistics_from_table).
  float threshold = 0;
  significance::ScoreStatistics statistics;
  bool statistics_from_table = false;
  // The contrast offset of the last frame, and where the logarithmic-phase check raised it (OnlineMapConfig).
  float contrast_offset = 0;
  std::vector<mapping::OnlineMapper::OffsetChange> offset_changes;
  // Images of little information (dark or near-uniform: soft-masked, OnlineMapper::next_frame_low_information).
  std::vector<std::size_t> low_information_frames;
  std::vector<std::string> warnings;  // about the input (a video that ended before the frames it announced)
  double seconds = 0;                 // the online run's wall time, reading and decoding included [s]
  std::map<std::string, std::size_t> event_counts;        // by event name (mapping::to_string)
  std::optional<evaluation::LoopClosureMetrics> metrics;  // of `loop_closures`, with a ground truth
  std::optional<MapRun> offline;                          // OnlineMapRequest::offline_map
};

// The map's options the online mapper reads, applied to `config` as the offline map applies them to its preset
// (apply_overrides, map_request.hpp): the shared sections (gap, threshold, cap, e_value, min_separation, contrast
// window and offset, reverse) and frames_per_place. min_separation and the contrast window count frames unless
// frames_per_place is given: the online map estimates no place scale before it aligns.
void apply_overrides(mapping::OnlineMapConfig& config, const MapOverrides& overrides);

// Called after each frame with its events (possibly none), and once after the last frame with finish()'s.
using OnlineMapFrameCallback = std::function<void(std::size_t frame, std::span<const mapping::OnlineEvent> events)>;

// Throws InputError naming the file for bad input (unreadable image, a bag, descriptors of another length, a ground
// truth of another size).
OnlineMapRun run_online_map(const OnlineMapRequest& request, const OnlineMapFrameCallback& on_frame = {});

// The standing loop closures as scored pairs (score = confidence), for evaluation::evaluate_loop_closures.
std::vector<evaluation::ScoredPair> online_scored_pairs(const std::vector<mapping::OnlineLoopClosure>& closures);

}  // namespace seqtopo::pipeline
