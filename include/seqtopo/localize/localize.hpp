#pragma once
// Sequence-based localization of a query traverse inside a mapped one (the kidnapped robot with a camera):
// the query x map similarity matrix is aligned with the local-alignment engine of the mapping paper
// (section IV-B, forward and reverse passes, cap, Waterman-Eggert declumping) and every query frame takes its
// map frame from the alignments that cover it.
//
// Orientation: rows are query frames, columns map frames (as in baseline/seqslam.hpp), so the query is
// sequence A of the engine and the map is B. A query driven along the map in the opposite direction is
// an anti-diagonal line and is found by the reverse pass.
//
//   SimilarityMatrix s = ...;                       // query x map, higher = more similar
//   LocalizeResult r = localize_sequence(s);        // r.frames[q].map, .confidence, .covered
//
// Scores. Each row is first contrast-enhanced (score_matrix): every cell becomes its z-score against the
// cells of the same row within +-contrast_window map frames, minus `contrast_offset`. The alignment then rewards a
// cell that stands out of its neighbourhood by more than `contrast_offset` standard deviations and penalises the
// rest, whatever the scale of the similarity (kappa drops out). Row-local, so the online localizer can do
// the same with one row at a time.
//
// Speed. A query recorded at another speed than the map is a path that is not at 45 degrees: every map
// frame skipped (faster) or every query frame repeated on one map frame (slower) costs one gap. The path still
// pays while a matched frame gains more than the gaps per frame cost, e.g. at half speed gain > gap, which a
// query at 1.5 or 2 times the map's speed does not (Nordland winter at 1.5x in summer: R@1 0.51; at 2x 0.02).
// So the map is also searched at other speeds (LocalizeConfig::speeds, as SeqSLAM searches trajectories of several
// velocities, Milford & Wyeth 2012): its columns resampled so the query's path is at 45 degrees again. Every
// E-value counts all the searches, so the speeds tried cost significance (a Bonferroni correction).
//
// Significance (significance/score_statistics.hpp). The alignments are found down to any positive score, best
// first, and the declumped ones that are not shadows of earlier ones are a sample of chance alignments once the
// real ones at the top are set aside: their extreme-value fit gives every alignment an E-value, the number of
// alignments this good expected by chance in a search of this query against this map (both directions).
//
// Per-frame result: posterior decoding (align/pair_posterior.hpp). Every alignment's band (+-posterior_band
// map frames around its path, and posterior_band query frames before its first pair and after its last)
// gives each of its rows the map frame of highest posterior and the posterior within +-tolerance map frames of
// it; past the alignment's ends the band follows the revisit the alignment's maximum stopped short of. The
// frame's confidence that this map frame is right is
//   confidence = P(revisit | E) * posterior,
// P(revisit | E) = 1 / (1 + E / significance.max_e_value) the probability that the alignment is real
// (significance::revisit_probability), and the posterior the probability that the revisit passes there (given
// that the row is on the alignment, between its first and last pair), with lambda from the fit. Without a
// fit (a search too small for one, or one with too few chance alignments) P(revisit | E) is replaced by 1 for
// alignments scoring at least `threshold`, 0 below, and lambda is Karlin & Altschul's of the cells
// (significance::ungapped_lambda). Alignments that run through a frame (between their first and last pair) at map
// frames more than `tolerance` apart are rival accounts of it (a look-alike stretch of the map): each one's
// confidence there is multiplied by its share of their weights P(revisit | E) exp(lambda * path score), so a
// frame whose evidence is split between look-alike places says so. Among the
// alignments whose band reaches a frame the most confident wins (then the higher local score, then the
// better-ranked alignment); the others give the runner-up candidates (recall@5). A frame no band reaches
// takes the best cell of its scored row, confidence 0. Every frame so has a best guess; it is "in the map"
// when its confidence is at least `min_confidence`, a decision on the confidence the user can move.
//
// Local score: the alignment's own score within +-score_window query frames of the frame (cell scores of its
// pairs there minus the gaps there), kept beside the confidence as the evidence in score units.
#include <cmath>
#include <cstddef>
#include <iterator>
#include <optional>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/settings.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/significance/score_statistics.hpp"

namespace seqtopo::localize {

// The longest lag LocalizeConfig::lag takes: each answer costs lag x map frames, and the last `lag` frames' answers
// at the query's end lag^2 x map frames.
inline constexpr std::size_t kMaxLag = 1000;
// The fastest and slowest speeds LocalizeConfig::speeds takes: kMaxSpeed and 1 / kMaxSpeed map frames per query frame.
inline constexpr double kMaxSpeed = 8;
// The speeds the query is searched at by default [map frames per query frame]: as recorded, and the query 1.5 and
// 2 times faster or slower.
inline constexpr double kDefaultSpeeds[] = {1.0, 1.5, 2.0, 1.0 / 1.5, 0.5};

struct LocalizeConfig {
  // The sections the map shares (align/settings.hpp), with localization's defaults. Row contrast enhancement
  // (similarity/contrast_enhancement.hpp): z-score against +-score.contrast_window map frames (0 = the whole row;
  // see score_matrix), minus score.contrast_offset. The search has no self pairs (search.min_separation 0). Below
  // significance.threshold an alignment counts as chance when the statistics cannot be fitted (see above), and it
  // is the online localizer's minimum confidence. significance.max_e_value is the E-value at which an alignment is
  // as likely a revisit as chance (significance::revisit_probability): the map's cut (mapping::MapConfig's), so a
  // localization is as sure as the map would be of the same alignment; it must be set. Windows count map frames.
  align::ScoreSettings score{.contrast_window = 10, .contrast_offset = 0.75F};
  align::SearchSettings search{.gap = 2.0F, .cap = std::nullopt, .reverse = true, .min_separation = 0};
  align::SignificanceSettings significance{.max_e_value = 0.01, .threshold = 10.0F};
  bool enhance = true;  // false: the similarity is used as given (minus score.contrast_offset)
  // Alignments found, best first: the real ones and a sample of chance ones for the statistics (as the map's fit).
  std::size_t max_alignments = 300;
  std::size_t score_window = 10;   // [query frames] half-width of the per-frame score window
  std::size_t candidates = 5;      // best map frames kept per query frame (for recall@k)
  std::size_t posterior_band = 8;  // [frames] the posterior's band either side of a path, and past its ends
  // [map frames] the posterior counts the guess's neighbours within this: the confidence is the probability of
  // a guess within +-tolerance of the truth, what the evaluation counts as right (seqtopo localize --tolerance).
  std::size_t tolerance = 2;
  double min_confidence = 0.5;  // a frame's guess below this confidence is "not in the map"
  unsigned threads = 1;         // forward and reverse passes in parallel when > 1; result does not depend on it
  // Online (OnlineLocalizer): each frame answered once this many later frames have arrived, with their evidence
  // (fixed-lag smoothing, OnlineLocalizer::smoothed). 0: at once, from the frames so far. At most kMaxLag.
  std::size_t lag = 0;
  // Offline: the speeds of the query against the map searched [map frames per query frame], 1 first, each within
  // [1 / kMaxSpeed, kMaxSpeed] (see "Speed" above). The query is aligned as recorded; the stretches where that leaves
  // frames unsure are aligned again at each other speed, once per phase of the frames it skips (a faster query
  // against the map's frames p + round(k * speed), a slower one with its frames p + round(k / speed)), with the
  // first search's statistics; every E-value counts all the searches, and an unsure frame takes the most confident
  // answer. The online localizer searches the recorded speed (1) only.
  std::vector<double> speeds = std::vector<double>(std::begin(kDefaultSpeeds), std::end(kDefaultSpeeds));
};

// Throws std::invalid_argument unless `speeds` lists at least one speed, each within [1 / kMaxSpeed, kMaxSpeed].
void validate_speeds(std::span<const double> speeds);

struct FrameMatch {
  bool covered = false;           // "in the map": confidence >= min_confidence (false = "not in the map")
  std::size_t map = 0;            // best guess of the map frame, given for every frame
  float score = 0;                // local alignment score around this frame (0 when no alignment reaches it)
  double confidence = 0;          // probability the guess is right (see above)
  double e_value = std::nan("");  // of the alignment that gave the guess (NaN: none, or no fit)
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::size_t alignment = npos;  // index of that alignment in LocalizeResult::alignments (npos: none)
  align::Direction direction = align::Direction::forward;
  std::vector<std::size_t> candidates;  // best first, distinct; candidates[0] == map
};

struct LocalizeResult {
  std::vector<FrameMatch> frames;                 // one per query frame (row)
  std::vector<align::LocalAlignment> alignments;  // every alignment found, best first (a = query, b = map)
  std::vector<double> e_values;                   // one per alignment (NaN without a fit)
  significance::ScoreStatistics statistics;       // the fit (valid() false when there was none)
  // Several similarities: their weights in the fusion (descriptor_weights), and those of weight 0, left out as blind
  // (indices, ascending).
  std::vector<double> descriptor_weights;
  std::vector<std::size_t> blind_descriptors;
  // Several similarities: the fused enhanced scores before the offset (fused_score_matrix with contrast_offset 0),
  // what a figure of the run shows. Empty with one.
  SimilarityMatrix fused_enhanced;
};

// The matrix the alignment scores: contrast-enhanced rows minus the contrast offset (see above). Throws
// std::invalid_argument on an empty matrix or non-finite values.
SimilarityMatrix score_matrix(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});
// One row of it (the online localizer's path); identical to the matrix version's row.
void score_row(const float* similarity_row, std::size_t cols, const LocalizeConfig& config, float* out);

// Throws std::invalid_argument on an empty matrix, non-finite values or a negative/NaN setting.
LocalizeResult localize_sequence(const SimilarityMatrix& query_x_map, const LocalizeConfig& config = {});

// Several descriptors (one query x map similarity each, all of one shape), fused: each row of each matrix
// contrast-enhanced on its own, the enhanced values averaged with `weights` (empty: equally, as the map fuses its
// descriptors, mapping::enhanced_scores), then the offset subtracted. One matrix gives score_matrix; without
// enhancement the similarities themselves are averaged.
SimilarityMatrix fused_score_matrix(std::span<const SimilarityMatrix> query_x_map, const LocalizeConfig& config = {},
                                    std::span<const double> weights = {});
// One row of it from the descriptors' rows (`rows[d]`, `cols` values each; `out` aliases none of them); identical to
// the matrix version's row. `scratch` holds cols values.
void fused_score_row(std::span<const float* const> rows, std::size_t cols, const LocalizeConfig& config, float* out,
                     float* scratch, std::span<const double> weights = {});

// The weight of each descriptor in the fusion, by how much it scores the revisits the descriptors find alone. Each
// is localized alone; the pairs of the alignments at E <= significance.max_e_value / D (a test per descriptor) are the
// revisits seen. A descriptor's weight is its mean enhanced score on them above its mean over the whole matrix:
// the shift a revisit gives its scores, whose noise is 1 after enhancement, so the weighted sum is the matched
// filter of the descriptors' evidence (a descriptor that barely sees the revisit adds its noise almost unweighted
// in an equal average: docs/localization-nordland.md). Weight 0, as the map's blind-descriptor rule
// (mapping::MapConfig::drop_blind_descriptors), for a descriptor that finds nothing alone at E <=
// significance.max_e_value and whose shift is within 3 standard errors of 0. Equal weights (all 1) with one matrix,
// without enhancement, or when no descriptor alone sees a revisit.
std::vector<double> descriptor_weights(std::span<const SimilarityMatrix> query_x_map,
                                       const LocalizeConfig& config = {});

// The localization of several descriptors' similarities, fused with their weights (descriptor_weights; those of
// weight 0 left out, result.blind_descriptors). One matrix: localize_sequence of it. Each similarity is
// contrast-enhanced once, for the weights and the fusion alike: the D enhanced tables are held together (D query x
// map tables of floats beside the similarities).
LocalizeResult localize_sequence(std::span<const SimilarityMatrix> query_x_map, const LocalizeConfig& config = {});

// Frames of little information (dark or near-uniform images: significance/low_information.hpp, each sequence by
// its own median), sorted. Their scores are at most 0 once aligned (soft-masked, as the map masks them): a dark
// query frame matching a dark map frame elsewhere (two different tunnels) is no evidence of where the query is,
// and a query through a tunnel the map saw too is placed by the evidence on either side.
struct LowInformationFrames {
  std::vector<std::size_t> query, map;
};
// `scores` (query x map, aligned: after the offset) with every cell of a listed query row or map column at most 0.
// Throws std::invalid_argument for a frame outside the matrix.
void soft_mask(SimilarityMatrix& scores, const LowInformationFrames& frames);
// localize_sequence with those frames soft-masked (none listed: the same as without).
LocalizeResult localize_sequence(std::span<const SimilarityMatrix> query_x_map, const LocalizeConfig& config,
                                 const LowInformationFrames& low_information);
// The localization of a score matrix already made (score_matrix, fused_score_matrix): the rest of localize_sequence.
LocalizeResult localize_scores(const SimilarityMatrix& scores, const LocalizeConfig& config = {});
// Its first half: the alignments, their E-values and the statistics, without the per-frame answers (frames empty).
LocalizeResult search_scores(const SimilarityMatrix& scores, const LocalizeConfig& config = {});

// Per-frame result from alignments already found on `scores` (the matrix the alignments scored), best first,
// with their E-values (NaN = no fit) and lambda: the second half of localize_sequence, exposed for callers
// that run the engine themselves.
std::vector<FrameMatch> frames_from_alignments(const std::vector<align::LocalAlignment>& alignments,
                                               const std::vector<double>& e_values, double lambda,
                                               const SimilarityMatrix& scores, const LocalizeConfig& config);

// The single-image baseline: each query frame takes the most similar map frame (ties: the smaller index);
// score = that similarity, candidates = the `candidates` most similar map frames. Every frame is covered.
std::vector<FrameMatch> single_frame_matches(const SimilarityMatrix& query_x_map, std::size_t candidates = 5);

// Throws std::invalid_argument naming the problem when the config is unusable.
void validate(const LocalizeConfig& config);

}  // namespace seqtopo::localize
