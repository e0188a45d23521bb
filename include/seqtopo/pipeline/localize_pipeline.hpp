#pragma once
// `seqtopo localize` as a library call: where in a mapped traverse is the robot? The query x map similarity is
// aligned offline (localize/localize.hpp), or the query frames are taken one at a time (online,
// localize/online_localizer.hpp); with ground truth, the answers are scored next to the single-frame and the
// SeqSLAM baselines on the same matrix (baselines.hpp). Writing the results is outputs/localize_outputs.hpp.
//
//   pipeline::LocalizeRequest request;
//   request.map = {{"summer"}};
//   request.query = {"winter"};
//   pipeline::LocalizeRun run = pipeline::localize_sequences(request);   // run.answers[q].map
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/evaluation/calibration.hpp"
#include "seqtopo/evaluation/localization_metrics.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/pipeline/ground_truth.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

namespace seqtopo::pipeline {

struct LocalizeSettings {
  SimilarityConfig similarity;  // its `descriptor` is not read: `descriptors` says which
  // One query x map similarity per descriptor, fused as the map fuses its descriptors, a blind one left out
  // (localize::localize_sequence): the map's default (MapSettings::descriptors). A descriptors.npy or similarity.npy
  // input is one matrix whatever this says.
  std::vector<Descriptor> descriptors{Descriptor::joint_histogram, Descriptor::patch};
  // 360-degree panoramas get the heading-invariant descriptor, as the map's (MapSettings::detect_panoramas). Off
  // when the descriptors are chosen.
  bool detect_panoramas = true;
  localize::LocalizeConfig localize;
};

struct LocalizeRequest {
  // The map's sessions (seqtopo localize --map A [--map B ...]; one map is a list of one): the map frames are the
  // sessions' frames one after the other (columns of the similarity, map indices of the answers, in that order).
  std::vector<SequenceInput> map;
  SequenceInput query;  // path "-" (online only): image paths from next_query_path
  // A query x map similarity.npy instead of the two sequences (rows = query frames, columns = map frames).
  std::optional<std::filesystem::path> similarity_file;
  LocalizeSettings settings;
  bool online = false;
};

// One query frame's answer, whichever mode produced it.
struct FrameAnswer {
  // The best guess, given for every frame (offline and online).
  std::optional<std::size_t> map;
  bool in_map = false;  // the decision: confidence >= the minimum confidence
  float score = 0;      // local alignment score (online: the table value; with a lag, of the best path through it)
  // The probability that the guess is right (localize/localize.hpp; online from the frames so far,
  // localize/online_localizer.hpp).
  double confidence = 0;
  // Of the alignment that gave the guess (online: of its score in the search so far); NaN: none or no fit.
  double e_value = std::nan("");
  std::vector<std::size_t> candidates;  // best first
};

// The frames reported "in the map" (confidence >= the minimum), scored against the truth.
struct InMapDecision {
  std::size_t in_map = 0, correct = 0;
  double precision = 1, recall = 0;  // correct / in_map; correct / query frames with a true match
};

struct LocalizeRun {
  bool online = false;
  std::string inputs;         // "QUERY in MAP", or the similarity file (for the report)
  LocalizeSettings settings;  // what ran (its descriptors those used: npy for descriptors, panorama detected)
  // Offline with several descriptors: their weights in the fusion (localize::descriptor_weights) and those left out
  // as blind (indices into settings.descriptors).
  std::vector<double> descriptor_weights;
  std::vector<std::size_t> blind_descriptors;
  std::vector<std::string> notes;  // what the run decided (panoramas detected, a descriptor left out), in order
  // query x map (offline, or the rows seen online): the similarity of one descriptor, or the fused contrast-enhanced
  // scores of several (localize::fused_score_matrix with a contrast offset of 0)
  SimilarityMatrix similarity;
  // Offline with several descriptors: each one's query x map similarity (named), which the baselines also run on.
  std::vector<std::pair<std::string, SimilarityMatrix>> descriptor_similarities;
  std::size_t queries = 0, maps = 0;
  std::vector<std::size_t> map_session_frames;  // map frames of each map session (one entry for one map)
  std::vector<FrameAnswer> answers;
  // Offline: the alignments that may be real (E-value at most 1, or without a fit scoring at least the
  // threshold), best first, and their E-values (NaN without a fit). The chance ones behind the statistics and
  // the low-confidence guesses are not kept.
  std::vector<align::LocalAlignment> alignments;
  std::vector<double> e_values;
  significance::ScoreStatistics statistics;  // offline
  // Online, per frame [s]: the latency is the processing, from the frame's arrival (its path or file read) to its
  // answer (decoding, describing, aligning); the wait is the time before it arrived, since the previous answer.
  std::vector<double> latencies, waits;
  SequenceInput map_input, query_input;  // what was read (empty paths for a similarity file): report thumbnails
  std::vector<std::pair<std::string, double>> timings;
  double seconds = 0;  // the localization's wall time
  // With ground truth (evaluate_localization_run):
  std::optional<evaluation::LocalizationMetrics> metrics, single_frame, seqslam;
  std::string seqslam_method;                          // the baseline's configuration, as the report names it
  std::optional<evaluation::Calibration> calibration;  // the confidence against the truth
  std::optional<InMapDecision> decision;
  std::size_t tolerance = 0;
};

// Online: called after every query frame with its index, answer, latency (processing) and wait [s].
using OnlineQueryCallback =
    std::function<void(std::size_t query, const FrameAnswer& answer, double latency, double wait)>;
// The next image path of a query given as "-" (nullopt at the end).
using NextPath = std::function<std::optional<std::string>()>;

// Throws InputError on unreadable or inconsistent inputs, std::invalid_argument on misuse.
LocalizeRun localize_sequences(const LocalizeRequest& request, const OnlineQueryCallback& on_frame = {},
                               const NextPath& next_query_path = {});

// Scores the answers against the truth (within +-tolerance map frames) and runs the single-frame and SeqSLAM
// baselines on the run's matrix and on each descriptor's, reporting for each baseline the one that suits it best
// (the higher recall@1, then AUC).
void evaluate_localization_run(LocalizeRun& run, const evaluation::LocalizationTruth& truth, std::size_t tolerance,
                               unsigned threads);

std::vector<evaluation::LocalizationPrediction> predictions(const std::vector<FrameAnswer>& answers);

}  // namespace seqtopo::pipeline
