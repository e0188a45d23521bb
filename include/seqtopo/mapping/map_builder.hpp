#pragma once
// The mapping paper end to end, from a similarity matrix: forward and reverse self alignments with
// the score cap -> per-column pruning -> transitive labels -> topological map, with the significance of
// every alignment (E-values from the sequence's own score statistics). One call, pure.
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/locally_optimal.hpp"
#include "seqtopo/align/score_source.hpp"
#include "seqtopo/align/settings.hpp"
#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/mapping/consistent_labels.hpp"
#include "seqtopo/mapping/odometry_gate.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/mapping/pruning.hpp"
#include "seqtopo/mapping/topological_map.hpp"
#include "seqtopo/significance/score_statistics.hpp"

namespace seqtopo::mapping {

// The labels of the images (offline only): which alignments' pairs become one place.
struct LabelSettings {
  // consistent: one labelling from all alignments (consistent_labels.hpp), each place holding at most
  // max_visit_span [places] of one pass; pruned_transitive: the paper's per-column pruning (pruning.hpp) and
  // transitive labels (place_labels.hpp).
  enum class Method { consistent, pruned_transitive };
  Method method = Method::consistent;
  double max_visit_span = 2;  // [places]
  PruningConfig pruning;
};

// The odometry, when build_map is given one (offline only).
struct OdometrySettings {
  // Alignments the gate contradicts are dropped before the labels. Chosen on the simulated worlds
  // (bench/worlds.sh); the real sequences in the README have no odometry.
  std::optional<OdometryGate> gate = OdometryGate{};
  // With the gate and the significance statistics: agreement with the odometry is evidence of its own. A chance
  // alignment agrees with probability q, estimated on the statistics' run (its chance alignments, E > 1, that
  // pass the gate: (passed + 1) / (tested + 2), from at least 20). Scores and agreement being independent under
  // chance, an alignment that agrees has E-value E x q / L, L = exp(-r^2 / 2) the relative likelihood of its
  // agreement r (odometry_agreement: 0 perfect, 1 at the gate's edge) for a true revisit whose odometry error is
  // Gaussian with the gate's allowance as its deviation; at most E. So the engine looks down to the score of
  // max_e_value / q, and each alignment the gate keeps reports that E-value and stays only when it is at most
  // max_e_value. An alignment at the edge of the allowance gains least: look-alike places a few metres apart
  // (parallel corridors) agree with an odometry that has drifted that far.
  bool evidence = true;
};

// The place graph before its topology is read (offline only).
struct GraphSettings {
  // Clean-up (graph_cleanup.hpp: overhangs, tips, bubbles, redundant edges), with thresholds of
  // min_revisit_places and the alignments' own lengths.
  bool clean = true;
  TopologyConfig topology;
};

struct MapConfig {
  // The shared sections (align/settings.hpp). Contrast enhancement: the aligned score is 0.5 (E + E^T) -
  // contrast_offset, in standard deviations of each row's neighbourhood; contrast_window = 0 aligns the raw
  // S = 1 - kappa D, as the paper does. The offset is the smallest tried: with phase.adapt_offset it is raised
  // until chance alignments stay short. Two checks (docs/significance.md): the chance alignments' median length
  // (at most max(4, ln(area)) places), and the global alignment rate of a table drawn from the scores (at most
  // phase.max_global_rate a step), which sees the phase in sequences too short for the lengths.
  align::ScoreSettings score;
  align::PhaseSettings phase;
  align::SearchSettings search;  // the cap below replaces search.cap when cap_from_statistics applies
  align::SignificanceSettings significance;
  // Windows and separations in places: each place spans frames_per_place images (place_scale.hpp), estimated
  // from the similarity when nullopt. Unit::frames counts them in frames, as the paper does.
  align::Unit unit = align::Unit::places;
  std::optional<double> frames_per_place;
  // Hubness correction of every similarity before its contrast enhancement (similarity/hubness.hpp): a pair
  // counts by how much more alike its frames are than each frame is to its hubness_neighbours most similar frames
  // elsewhere in the sequence, so frames that resemble much of it (dark tunnels, bare walls) stop standing out of
  // the ordinary frames around them. [unit]; 0: off. With contrast enhancement only. Off by default: with
  // low-information masking it adds little and costs real revisits (docs/significance.md, "Trust").
  double hubness_neighbours = 0;
  // With significance (significance.max_e_value set) and cap_from_statistics, the cap is cap_factor times the
  // score a significant alignment must reach, so the stretch of non-matching images that separates two revisits
  // follows the sequence's own statistics; else search.cap.
  bool cap_from_statistics = true;
  float cap_factor = 3.0F;
  // Shorter revisits are dropped [places].
  double min_revisit_places = 3;
  // exact: the scalar reference engine (align/smith_waterman.hpp, a float table of N x N cells);
  // fast: the vectorized linear-memory engine (align/fast_alignment.hpp) on scores quantized to
  // 1/512 of a unit with the default cap: the same alignments as the exact engine on those scores.
  enum class Engine { exact, fast };
  Engine engine = Engine::exact;
  // The revisits reported (align/locally_optimal.hpp): non_intersecting, the Waterman-Eggert set (no two
  // alignments share a pair; the configured engine); locally_optimal, every locally optimal alignment after
  // Schmidt and Sellers (the float implementation whatever the engine: one float and one byte per cell).
  // The significance statistics are fitted on the non-intersecting set in both cases (docs/alignment_sets.md).
  align::AlignmentSet alignment_set = align::AlignmentSet::non_intersecting;
  // The offline-only sections.
  OdometrySettings odometry;
  LabelSettings labels;
  GraphSettings graph;
  unsigned threads = 2;
  // Declumped alignments found for the statistics' fit (significance/score_statistics.hpp).
  std::size_t fit_alignments = 300;
  // Half-width of the band the pairs' posteriors sum over [frames]; at least one place.
  std::size_t confidence_band = 8;
  // A pair's confidence is the probability that its image lies within this many frames of the partner the map
  // gives it (or one place, when a place spans more): the tolerance place recognition is evaluated with
  // (seqtopo localize --tolerance, the same default).
  std::size_t confidence_tolerance = 2;
  // With the significance statistics: alignments' ends cut back where their pairs are more likely chance than
  // revisit (significance/alignment_ends.hpp).
  bool trim_chance_ends = true;
  // With several similarities, the significance statistics and contrast enhancement, for sequences of at most
  // max_blind_check_frames frames: each descriptor is mapped alone first, and one that is blind is left out of
  // the fusion: its own map has no loop closure, another's has one at E <= max_e_value / D, and on that map's
  // pairs its enhanced scores are no higher than on its chance cells (within 3 standard errors). Its scores would
  // be noise averaged into the others' evidence (the joint histogram's absolute colour bins on a lap recorded darker:
  // docs/significance.md); a descriptor too weak to map alone that still scores the revisit stays
  // (decisions.blind_descriptors).
  bool drop_blind_descriptors = true;
  std::size_t max_blind_check_frames = 8000;
  // Frames of little information given to build_map (dark or near-uniform images: significance/low_information.hpp)
  // carry no evidence of a revisit, as a sequence search masks low-complexity regions: with contrast enhancement
  // the statistics' fit and the alignment leave them out (a stretch of them is a free step), so an alignment cannot
  // be made of them but runs across them between two real matches, whether the stretch is in both passes (a tunnel
  // driven through twice) or in one (the lights out): a revisit on either side stays one revisit. Where both passes
  // skip frames there, its pairs lie on the straight line between the evidence on either side. The outputs' scores
  // show them capped at the contrast offset (aligned, at most 0). false: every frame is aligned as it scores.
  bool mask_low_information = true;
  // Not a setting: told the run's progress as (what, done, total), each step counting its own units: "similarities
  // enhanced" (of those fused), "descriptors mapped alone" (the blind check), "statistics' fits" (one per contrast
  // offset tried, of those that could be), "cells aligned" (the main alignment's passes, forward and reverse, told
  // from their threads). Empty: nobody is told.
  std::function<void(std::string_view what, std::size_t done, std::size_t total)> progress = {};
};

// What a map run decided from the sequence itself (the settings in frames, the statistics), for the report.
struct MapDecisions {
  double frames_per_place = 1;  // estimated or given
  bool frames_per_place_estimated = false;
  std::size_t contrast_window = 0;  // [frames]
  std::size_t min_separation = 0;   // [frames]
  std::size_t min_revisit_pairs = 0;
  float contrast_offset = 0;                 // the offset aligned with (after adapt_offset)
  std::optional<float> cap;                  // the cap aligned with
  float score_threshold = 0;                 // the capped score a revisit needs
  significance::ScoreStatistics statistics;  // invalid without significance or when the fit failed
  double chance_mean = 0;                    // mean score of the cells the fit read, off the self band
  double chance_length = 0;                  // median length of the fitted chance alignments [places]
  // odometry_evidence: the probability q that a chance alignment agrees with the odometry (1: not used).
  double odometry_chance_agreement = 1;
  std::size_t similarities = 1;  // how many build_map fused (1 for the other entry points)
  // drop_blind_descriptors: the similarities (indices into build_map's list) left out of the fusion.
  std::vector<std::size_t> blind_descriptors;
  // mask_low_information: the frames taken out as carrying no evidence (sorted).
  std::vector<std::size_t> low_information_frames;
  // What was adapted and why, as facts (formats/decision_notes.hpp says them in words, one line each):
  bool place_scale_missing = false;  // the scale was estimated but none found: windows count frames
  // Each contrast offset the statistics' run found in the linear phase, in order: raised to the next (adapt_offset),
  // or the last tried, kept although its revisits may be overestimated.
  struct LinearPhase {
    float offset = 0;
    bool by_global_rate = false;     // the scores' global alignment rate above max_global_rate (else chance alignments
                                     // grew long)
    double global_rate = 0;          // [score units a step]
    double bound = 0;                // the phase's max_global_rate (0 when unset)
    double chance_length = 0;        // [places]
    std::optional<float> raised_to;  // unset: kept
  };
  std::vector<LinearPhase> linear_phase;
  // Too few chance alignments to fit the statistics: how many (the fixed threshold and cap applied are
  // score_threshold and cap).
  std::optional<std::size_t> unfitted_chance_alignments;
  std::size_t trimmed_chance_end_pairs = 0;  // aligned pairs at ends more likely chance than revisit, trimmed off
  std::size_t trimmed_odometry_pairs = 0;    // aligned pairs past where two paths part (the odometry), trimmed off
  std::size_t tandem_repeat_frames = 0;      // frames masked as tandem repeats of appearance (beyond the dark ones)
};

struct MapResult {
  SimilarityMatrix scores;                         // what was aligned (S, or its contrast-enhanced form); empty
                                                   // from build_map_from_scores
  std::vector<align::LocalAlignment> alignments;   // best first, forward and reverse merged
  std::vector<align::LocalAlignment> rejected;     // found, but contradicted by the odometry (not in `alignments`)
  std::vector<OdometryVerdict> rejected_verdicts;  // why, one per `rejected` (apart or turned)
  // Per alignment (parallel to `alignments`): the score of its path without the cap, and its E-value (NaN
  // without significance).
  std::vector<double> path_scores, e_values;
  // Found by the statistics' run but not significant, or shorter than a revisit: what the filter removed
  // (best first, with their E-values), and why.
  std::vector<align::LocalAlignment> insignificant;
  std::vector<double> insignificant_e_values;
  MapDecisions decisions;
  PruningResult pruning;  // the retained pairs (accepted by the labelling, or surviving pruning)
  TopologicalMap map;
  // Per alignment, per pair: the posterior that the pair is aligned (align/pair_posterior.hpp); empty for the
  // alignments that gave no retained pair. Each retained pair's confidence is in pruning.pairs.
  std::vector<std::vector<double>> posteriors;
  double seconds_align = 0, seconds_prune_label = 0, seconds_confidence = 0;
};

// The pipeline, from the similarity matrices of one sequence:
//  1. frames per place (place_scale.hpp) estimated from the similarities, unless given or the unit is frames;
//     windows and separations are converted to frames;
//  2. each matrix contrast-enhanced on its own (so their scales need not agree) and the enhanced scores
//     averaged (enhanced_scores); without contrast enhancement the raw matrices are averaged;
//  3. with significance (significance.max_e_value): the statistics' run (the best fit_alignments declumped alignments
//  of
//     the scores minus the offset, fast engine) fits lambda and K (significance/score_statistics.hpp) and
//     checks the phase: while chance alignments grow with the sequence the offset is raised; the cap and the
//     score a revisit needs follow from the fit (MapDecisions);
//  4. forward and reverse self alignments with the cap (the configured engine), every alignment's E-value
//     from its uncapped path score (times the odometry's chance agreement for those that agree, with
//     odometry_evidence), revisits shorter than min_revisit_places dropped; the odometry gate;
//  5. consistent labels (or per-column pruning and transitive labels), the graph clean-up, topology.
// Throws std::invalid_argument for a non-square or empty matrix, odometry of another length, or a config that
// check_map_config refuses. `odometry` (one pose per image, or empty) feeds config.odometry.gate.
// Throws std::invalid_argument naming the first setting out of its range (the command line's limits: a
// negative gap or threshold, an E-value, cap or frames per place that is not positive, ...).
void check_map_config(const MapConfig& config);

MapResult build_map(const SimilarityMatrix& similarity, const MapConfig& config = {},
                    std::span<const Pose2> odometry = {});
MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config = {},
                    std::span<const Pose2> odometry = {});
// The same with the frames of little information (sorted indices; significance/low_information.hpp) masked as
// MapConfig::mask_low_information says (decisions.low_information_frames lists them). Throws
// std::invalid_argument for an index out of range.
MapResult build_map(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config,
                    std::span<const Pose2> odometry, std::span<const std::size_t> low_information);

// Steps 3-5 on contrast-enhanced scores without the offset (0.5 (E + E^T), or S itself when contrast_window is
// 0), from any score source: a dense matrix, or scores streamed from descriptors (scale/streaming_similarity.hpp,
// with the window in frames: settings_in_frames). config.frames_per_place is the scale (1 when nullopt). The
// exact engine fills an N x N table whatever the source; a source that is not held in memory wants
// Engine::fast (1/8 byte per cell, docs/engine.md). seconds_align includes the reads of `enhanced`.
// `run_alignment`, when given, replaces the engine of step 4 (the statistics' run of step 3 stays the fast engine on
// `enhanced`): it gets the engine settings, the offset the scores it must align are `enhanced` minus, the frames
// it must leave out and those whose scores it must soft-mask (at most 0 once shifted; each empty: none), and
// returns the alignments, best first, of the frames not left out as one sequence (its frame k the k-th frame not
// left out). The sparse mode aligns its candidate cells this way (pipeline).
using AlignmentRun = std::function<std::vector<align::LocalAlignment>(const align::AlignConfig& engine, float offset,
                                                                      const std::vector<bool>& left_out,
                                                                      const std::vector<bool>& masked)>;
// `low_information` (sorted frame indices, build_map's) are frames of little information: with contrast
// enhancement and mask_low_information (build_map's rule) the statistics and the alignment leave out their
// stretches at least the self-alignment band long (a free step, so a revisit runs across a tunnel in one pass or
// both) and soft-mask the others; their pairs are placed between the evidence on either side and cut at the
// alignments' ends.
MapResult build_map_from_enhanced(const align::ScoreSource& enhanced, const MapConfig& config = {},
                                  std::span<const Pose2> odometry = {}, const AlignmentRun& run_alignment = {},
                                  std::span<const std::size_t> low_information = {});

// Steps 3-5 on scores aligned as they are (no offset, no place units): the engine's own view.
MapResult build_map_from_scores(const align::ScoreSource& scores, const MapConfig& config = {},
                                std::span<const Pose2> odometry = {});

// The engine settings of the config's gap, cap, threshold and min_separation (in frames: the unit is not
// applied), self alignment.
align::AlignConfig align_config(const MapConfig& config);

// Step 3's statistics alone: lambda and K fitted to the best config.fit_alignments declumped alignments of
// `scores` (aligned as they are, in frames: no offset, no place units), shadows left out and the first ranks set
// aside as real, looking up to 16 times as far when revisits and their shadows leave too few; area the self
// search's (both directions with config.reverse). Invalid when too few chance alignments remain. With the two
// checks of the logarithmic phase build_map makes before it trusts them (the scores' global alignment rate
// against config.max_global_rate; the chance alignments' median length in places against the log of the area in
// places). For a caller that holds the table of a short sequence (mapping/online_mapper.hpp, before its islands
// suffice).
struct TableFit {
  significance::ScoreStatistics statistics;
  double chance_length = 0;  // [places]
  double global_rate = 0;    // [score units a step]
  bool logarithmic = false;  // valid statistics, and both checks hold
};
TableFit fit_table_statistics(const align::ScoreSource& scores, const MapConfig& config, double frames_per_place = 1);

// The topology settings of step 5 for a config in frames (the clean-up's transitive reduction and junction regions).
TopologyConfig topology_settings(const MapConfig& config);

// The config with its windows and separations converted from places to frames (unchanged in Unit::frames).
MapConfig settings_in_frames(const MapConfig& config, double frames_per_place);

// The mean of estimate_frames_per_place over the matrices that have a scale (not found when none has).
PlaceScale frames_per_place(const std::vector<SimilarityMatrix>& similarities);

// Step 2: the fused contrast-enhanced scores without the offset (S itself when contrast_window is 0); `told`
// (when set) after each similarity, with how many are done of how many.
SimilarityMatrix enhanced_scores(const std::vector<SimilarityMatrix>& similarities, std::size_t contrast_window,
                                 const std::function<void(std::size_t done, std::size_t total)>& told = {});
// The same minus config.contrast_offset (no place units: config's window in frames).
SimilarityMatrix alignment_scores(const std::vector<SimilarityMatrix>& similarities, const MapConfig& config);

}  // namespace seqtopo::mapping
