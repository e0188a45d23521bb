#pragma once
// One call from a sequence (image folder, video, descriptors.npy or similarity.npy) to the similarity
// matrix S = 1 - kappa * D of the mapping paper (section IV-A). The parts are usable on their own:
// image_io.hpp and sequence_input.hpp (reading), joint_histogram.hpp and patch_thumbnail.hpp (descriptors),
// seqtopo/similarity/* (distances, matrix, kappa).
//
//   auto result = seqtopo::pipeline::compute_similarity({"data/rtabmap-corridor"});
//   // result.similarity: 84 x 84, result.kappa chosen by the rule in similarity_from_distance.hpp
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"
#include "seqtopo/image/joint_histogram.hpp"
#include "seqtopo/image/panorama_signature.hpp"
#include "seqtopo/image/patch_thumbnail.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/similarity/distance.hpp"
#include "seqtopo/similarity/similarity_from_distance.hpp"

namespace seqtopo::pipeline {

// npy = rows of descriptors.npy; panorama = heading-invariant signature of 360-degree images
enum class Descriptor { joint_histogram, patch, panorama, npy };
using Distance = similarity::Distance;

// "joint-histogram", "patch", "panorama", "npy"; throws std::invalid_argument otherwise.
Descriptor parse_descriptor(std::string_view name);
std::string_view descriptor_name(Descriptor descriptor);
// A comma-separated list of names ("joint-histogram,patch"); throws std::invalid_argument on an unknown name or
// an empty list. descriptor_names is its inverse.
std::vector<Descriptor> parse_descriptors(std::string_view names);
std::string descriptor_names(std::span<const Descriptor> descriptors);
// chi2 for histograms, sad for thumbnails and panorama signatures, cosine for external descriptors.
Distance default_distance(Descriptor descriptor);

struct SimilarityConfig {
  Descriptor descriptor = Descriptor::joint_histogram;  // a descriptors.npy input always uses its rows
  std::optional<Distance> distance;                     // default by descriptor: default_distance()
  std::optional<float> kappa;                           // nullopt = auto (kappa_rule)
  unsigned threads = 0;                                 // 0 = all cores
  image::JointHistogramConfig joint_histogram;
  image::PatchConfig patch;
  image::PanoramaConfig panorama;
  similarity::KappaRule kappa_rule;
  std::size_t tile = 64;  // matrix tile side [cells]

  // Reports from long stages (never printed by the library): progress(stage, done, total) and notes such
  // as the memory estimate made before the matrix is allocated. Both are called from one thread at a time.
  std::function<void(std::string_view, std::size_t, std::size_t)> progress;
  std::function<void(std::string_view)> note;
  std::size_t note_memory_above = std::size_t{64} << 20U;  // [bytes] estimates below this are not reported
  // Image folders: called with each image as it is decoded (its row, counted over the sessions one after the
  // other, and the image), from the worker threads, so that what else needs the pixels (the report's thumbnails)
  // need not decode them again.
  std::function<void(std::size_t, const RgbImage&)> on_image;
  // The same for the columns' images when two sequences are compared (compute_similarities(a, b, ...): on_image
  // sees a's, this b's).
  std::function<void(std::size_t, const RgbImage&)> on_column_image;
};

// The user's choice of descriptors and of their comparison, by the options `map` and `localize` share
// (--descriptor, --metric, --kappa, --threads); unset: the settings' own. apply_descriptor_overrides applies them
// for the command line and Python alike: the descriptors asked for are the descriptors used (no panorama swap).
struct DescriptorOverrides {
  std::optional<std::vector<Descriptor>> descriptors = {};
  std::optional<Distance> metric = {};
  std::optional<float> kappa = {};
  std::optional<unsigned> threads = {};  // 0 = every core
};
// Throws std::invalid_argument on an empty descriptor list.
void apply_descriptor_overrides(const DescriptorOverrides& overrides, std::vector<Descriptor>& descriptors,
                                bool& detect_panoramas, SimilarityConfig& similarity);

struct SimilarityResult {
  SimilarityMatrix similarity;  // S, rows = first sequence, cols = second (or same)
  float kappa = 0;              // the kappa used (NaN when the input was a similarity matrix)
  bool kappa_auto = false;
  double kappa_fraction = 0;              // kappa auto: the fraction p of candidate pairs given S > 0
  std::optional<Distance> distance;       // nullopt when the input was a similarity matrix
  std::vector<std::string> frame_names;   // file names / "frame 17" / "row 17", one per row
  std::vector<std::string> column_names;  // one per column
  std::vector<std::size_t> session_rows;  // rows of each session of the first side (one entry for one input)
  // The grey-level entropy of each row's image [bits] (significance/low_information.hpp); empty unless every row
  // is an image or a video or bag frame.
  std::vector<double> frame_entropy;
  std::vector<double> column_entropy;  // the same of each column's image, when the columns are another sequence
  double seconds_descriptors = 0, seconds_matrix = 0;
};

// N x N of one sequence (symmetric). Bad input throws InputError naming the file, misuse
// std::invalid_argument; a matrix that would not fit in memory is refused with InputError.
SimilarityResult compute_similarity(const SequenceInput& input, const SimilarityConfig& config = {});
// N x M between two sequences: rows = a, cols = b. For InputKind::similarity on `a`, `b` is ignored and the
// N x M matrix is returned as is.
SimilarityResult compute_similarity(const SequenceInput& a, const SequenceInput& b,
                                    const SimilarityConfig& config = {});

// Several sessions as one sequence (seqtopo map S1 S2 ...): their frames one after the other, session by
// session; N x N over all of them, or N x M against `b`'s sessions. Every session must give the same kind of
// descriptor; a similarity.npy cannot be one of several. Frame names are prefixed with the session input's
// file name when there are several.
SimilarityResult compute_similarity(std::span<const SequenceInput> sessions, const SimilarityConfig& config = {});
SimilarityResult compute_similarity(std::span<const SequenceInput> a, std::span<const SequenceInput> b,
                                    const SimilarityConfig& config = {});
// One matrix per descriptor (config.descriptor is ignored), in that order, from one pass over the images: each
// image is read and decoded once for all of them. A similarity.npy input gives its one matrix; a
// descriptors.npy input is one descriptor. The pass's time is in the first result's seconds_descriptors.
std::vector<SimilarityResult> compute_similarities(std::span<const SequenceInput> sessions,
                                                   std::span<const Descriptor> descriptors,
                                                   const SimilarityConfig& config = {});
// The same N x M against `b`'s sessions (rows = a).
std::vector<SimilarityResult> compute_similarities(std::span<const SequenceInput> a, std::span<const SequenceInput> b,
                                                   std::span<const Descriptor> descriptors,
                                                   const SimilarityConfig& config = {});

// The same computation on descriptors already in memory (rows = images, as a descriptors.npy input; default
// distance cosine): N x N, or N x M against `against` (rows = `descriptors`). Throws std::invalid_argument
// on empty or non-finite rows, similarity::MemoryError when the matrix would not fit.
SimilarityResult similarity_of_descriptors(const DenseMatrix<float>& descriptors, const DenseMatrix<float>* against,
                                           const SimilarityConfig& config = {});

// The per-image vectors of one sequence, without any N x N matrix (for scores streamed from them,
// scale/streaming_similarity.hpp): the rows of a descriptors.npy, or the patch / panorama descriptor of
// every image or frame. A joint histogram has no vector form and a similarity.npy no descriptors: both
// throw InputError naming the input, as bad input does; misuse throws std::invalid_argument.
struct DescriptorResult {
  DenseMatrix<float> descriptors;           // N x dim, one row per image
  Descriptor descriptor = Descriptor::npy;  // the one used (npy for a descriptors.npy input)
  std::vector<std::string> frame_names;     // as in SimilarityResult
  std::vector<std::size_t> session_rows;    // as in SimilarityResult
  std::vector<double> frame_entropy;        // as in SimilarityResult
  double seconds_descriptors = 0;
};
DescriptorResult compute_descriptors(const SequenceInput& input, const SimilarityConfig& config = {});
DescriptorResult compute_descriptors(std::span<const SequenceInput> sessions, const SimilarityConfig& config = {});

// The dense descriptors (patch, panorama) of one image, and their length. Throws std::invalid_argument for
// joint_histogram and npy.
std::vector<float> dense_descriptor(const RgbImage& image, Descriptor descriptor, const SimilarityConfig& config);
std::size_t dense_dimension(Descriptor descriptor, const SimilarityConfig& config);

}  // namespace seqtopo::pipeline
