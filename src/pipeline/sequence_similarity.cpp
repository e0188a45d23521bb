#include "seqtopo/pipeline/sequence_similarity.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/stopwatch.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/machine_memory.hpp"
#include "seqtopo/significance/low_information.hpp"
#include "seqtopo/similarity/distance_matrix.hpp"
#include "seqtopo/similarity/memory.hpp"
#ifdef SEQTOPO_HAVE_RECORDING
#include "seqtopo/recording/recording.hpp"
#endif

namespace seqtopo::pipeline {

using image::for_each_video_frame;
using image::joint_histogram;
using image::JointHistogramConfig;
using image::load_image;
using image::panorama_signature;
using image::patch_thumbnail;
using image::video_frame_count;

Descriptor parse_descriptor(std::string_view name) {
  if (name == "joint-histogram" || name == "joint_histogram") return Descriptor::joint_histogram;
  if (name == "patch") return Descriptor::patch;
  if (name == "panorama") return Descriptor::panorama;
  if (name == "npy") return Descriptor::npy;
  throw std::invalid_argument("unknown descriptor '" + std::string(name) +
                              "' (expected joint-histogram, patch, panorama or npy)");
}

std::string_view descriptor_name(Descriptor descriptor) {
  switch (descriptor) {
    case Descriptor::joint_histogram:
      return "joint-histogram";
    case Descriptor::patch:
      return "patch";
    case Descriptor::panorama:
      return "panorama";
    case Descriptor::npy:
      return "npy";
  }
  return "?";
}

void apply_descriptor_overrides(const DescriptorOverrides& o, std::vector<Descriptor>& descriptors,
                                bool& detect_panoramas, SimilarityConfig& similarity) {
  if (o.descriptors) {
    if (o.descriptors->empty()) throw std::invalid_argument("no descriptor given");
    detect_panoramas = false;
    descriptors = *o.descriptors;
  }
  if (o.metric) similarity.distance = *o.metric;
  if (o.kappa) similarity.kappa = *o.kappa;
  if (o.threads) similarity.threads = *o.threads;
}

std::vector<Descriptor> parse_descriptors(std::string_view names) {
  std::vector<Descriptor> list;
  while (!names.empty()) {
    const std::size_t comma = names.find(',');
    list.push_back(parse_descriptor(names.substr(0, comma)));
    names = comma == std::string_view::npos ? std::string_view() : names.substr(comma + 1);
  }
  if (list.empty()) throw std::invalid_argument("no descriptor given");
  return list;
}

std::string descriptor_names(std::span<const Descriptor> descriptors) {
  std::string names;
  for (Descriptor d : descriptors) {
    if (!names.empty()) names += ',';
    names += descriptor_name(d);
  }
  return names;
}

Distance default_distance(Descriptor descriptor) {
  switch (descriptor) {
    case Descriptor::joint_histogram:
      return Distance::chi2;
    case Descriptor::patch:
      return Distance::sad;
    case Descriptor::panorama:
      return Distance::sad;
    case Descriptor::npy:
      return Distance::cosine;
  }
  return Distance::chi2;
}

std::vector<float> dense_descriptor(const RgbImage& image, Descriptor descriptor, const SimilarityConfig& config) {
  switch (descriptor) {
    case Descriptor::patch:
      return patch_thumbnail(image, config.patch);
    case Descriptor::panorama:
      return panorama_signature(image, config.panorama);
    default:
      throw std::invalid_argument("descriptor '" + std::string(descriptor_name(descriptor)) + "' is not dense");
  }
}

std::size_t dense_dimension(Descriptor descriptor, const SimilarityConfig& config) {
  switch (descriptor) {
    case Descriptor::patch:
      return static_cast<std::size_t>(std::max(0, config.patch.width)) *
             static_cast<std::size_t>(std::max(0, config.patch.height));
    case Descriptor::panorama:
      return config.panorama.dimension();
    default:
      throw std::invalid_argument("descriptor '" + std::string(descriptor_name(descriptor)) + "' is not dense");
  }
}

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

unsigned thread_count(unsigned requested) {
  return requested > 0 ? requested : std::max(1U, std::thread::hardware_concurrency());
}

// One sequence, resolved: what it is and how many items it has (known before any descriptor is computed,
// so that an impossible request is refused early).
struct Source {
  SequenceInput input;
  InputKind kind = InputKind::automatic;
  std::vector<fs::path> images;                           // kind images (only the kept frames)
  std::vector<std::pair<fs::path, std::string>> skipped;  // kind images: unreadable entries left out
  std::optional<std::size_t> count;                       // items, when known in advance
  std::optional<std::size_t> dimension;                   // descriptor length, when known in advance
  std::string image_topic;                                // kind bag
  std::vector<fs::path> unlisted;                         // kind bag: storage files metadata.yaml does not list
};

// Only the frames of input.frames (when given), checked against the number of frames.
template <typename T>
std::vector<T> kept_frames(std::vector<T> all, const SequenceInput& input) {
  if (input.frames.empty()) return all;
  std::vector<T> kept;
  for (std::size_t k : input.frames) {
    if (k >= all.size()) {
      throw InputError(input.path.string(), "frame " + std::to_string(k) + " was selected, but the sequence has " +
                                                std::to_string(all.size()) + " frames");
    }
    kept.push_back(std::move(all[k]));
  }
  return kept;
}

Source resolve(const SequenceInput& input) {
  if (input.every == 0) throw std::invalid_argument("every must be at least 1");
  Source s;
  s.input = input;
  s.kind = resolve_input_kind(input);
  switch (s.kind) {
    case InputKind::images: {
      ImageListing listing = list_input_images(input);
      s.images = kept_frames(std::move(listing.files), input);
      s.skipped = std::move(listing.skipped);
      s.count = s.images.size();
      break;
    }
    case InputKind::video:
      if (!input.frames.empty()) {
        s.count = input.frames.size();
      } else if (const auto frames = video_frame_count(input.path)) {
        s.count = every_kth_count(*frames, input.every);
      }
      break;
    case InputKind::bag: {
#ifdef SEQTOPO_HAVE_RECORDING
      const recording::Recording bag(input.path);
      s.image_topic = bag.image_topic(input.image_topic);
      s.unlisted = bag.unlisted_files();
      s.count =
          input.frames.empty() ? every_kth_count(bag.message_count(s.image_topic), input.every) : input.frames.size();
#else
      throw InputError(input.path.string(),
                       "this seqtopo was built without bag support (the recording module needs librosbag-dev, "
                       "libsqlite3-dev, libzstd-dev and liblz4-dev: scripts/setup.sh)");
#endif
      break;
    }
    case InputKind::descriptors:
    case InputKind::similarity: {
      const io::NpyHeader header = io::read_npy_header(input.path);
      if (header.shape.size() != 2) throw InputError(input.path.string(), "expected a 2-D array");
      s.count = input.frames.empty() ? every_kth_count(header.shape[0], input.every) : input.frames.size();
      if (s.kind == InputKind::similarity && !input.frames.empty()) {
        throw InputError(input.path.string(), "frames cannot be selected from a similarity matrix");
      }
      if (s.kind == InputKind::similarity) refuse_every_for_similarity(input);
      s.dimension = header.shape[1];
      break;
    }
    case InputKind::automatic:
      break;
  }
  return s;
}

Descriptor effective_descriptor(const Source& s, const SimilarityConfig& c) {
  if (s.kind == InputKind::descriptors) return Descriptor::npy;
  if (c.descriptor == Descriptor::npy) {
    throw InputError(s.input.path.string(), "descriptor npy needs a descriptors .npy file as input");
  }
  return c.descriptor;
}

// Bytes of one item's descriptor, for the estimate. A joint histogram stores at most one bin per pixel; the
// first image of a folder tells the pixel count (videos: every bin).
std::size_t descriptor_bytes(Descriptor d, const Source& s, const SimilarityConfig& c) {
  switch (d) {
    case Descriptor::joint_histogram: {
      std::size_t bins = JointHistogramConfig::bins;
      if (!s.images.empty()) {
        const image::ImageHeader first = image::image_size(s.images.front());
        bins = std::min(bins, static_cast<std::size_t>(first.width) * static_cast<std::size_t>(first.height));
      }
      return sizeof(similarity::SparseHistogram) + bins * (sizeof(std::uint32_t) + sizeof(float));
    }
    case Descriptor::patch:
    case Descriptor::panorama:
      return dense_dimension(d, c) * sizeof(float);
    case Descriptor::npy:
      return s.dimension.value_or(0) * sizeof(float);
  }
  return 0;
}

// Estimates the memory of the whole computation, reports it when large, refuses it when it cannot fit.
void check_memory(const Source& a, const Source* b, Descriptor d, const SimilarityConfig& c) {
  if (!a.count || (b && !b->count)) return;  // a video without a frame count: the matrix step checks again
  const std::size_t rows = *a.count, cols = b ? *b->count : *a.count;
  std::size_t total = similarity::matrix_bytes(rows, cols);
  const std::size_t per_item = descriptor_bytes(d, a, c);
  const std::size_t max = std::numeric_limits<std::size_t>::max();
  const std::size_t items = rows + (b ? cols : 0);
  const std::size_t desc = per_item != 0 && items > max / per_item ? max : items * per_item;
  total = total > max - desc ? max : total + desc;
  const auto available = available_memory_bytes();
  const std::string what =
      "the " + std::to_string(rows) + " x " + std::to_string(cols) + " similarity matrix with its descriptors";
  if (c.note && total >= c.note_memory_above) {
    c.note("memory estimate: " + what + " needs up to " + similarity::format_bytes(total) +
           (available ? " (" + similarity::format_bytes(*available) + " available)" : std::string()));
  }
  try {
    similarity::check_fits(total, available, what);
  } catch (const similarity::MemoryError& e) {
    throw InputError(a.input.path.string(), e.what());
  }
}

// Every descriptor asked for, from one pass over the images (each image is read and decoded once).
using Descriptors = std::span<const Descriptor>;

bool has_joint_histogram(Descriptors ds) { return std::ranges::find(ds, Descriptor::joint_histogram) != ds.end(); }

struct Described {
  std::vector<similarity::DescriptorSet> sets;  // one per descriptor, in the order asked
  std::vector<std::string> names;
  std::vector<std::size_t> session_rows;
  std::vector<double> entropy;              // grey-level entropy of each image [bits]; empty for descriptors
  std::optional<std::pair<int, int>> size;  // of the images or frames (one size when a joint histogram was made)
};

// Sessions (or the two sides of a comparison) whose images differ in size: an error for the joint histogram, as
// inside one folder (check_sizes): its fixed windows would see another scale in each, and no frame would match.
void check_same_size(const Described& first, const std::string& first_input, const Described& other,
                     const std::string& other_input, Descriptors ds) {
  if (!has_joint_histogram(ds) || !first.size || !other.size || *first.size == *other.size) return;
  throw InputError(other_input, "its images are " + std::to_string(other.size->first) + " x " +
                                    std::to_string(other.size->second) + " pixels, those of " + first_input + " " +
                                    std::to_string(first.size->first) + " x " + std::to_string(first.size->second) +
                                    ": the joint-histogram descriptor does not resize (its 3x3 and 5x5 windows would "
                                    "see a different scale in each); give images of one size, or --descriptor patch");
}

// Descriptor of one image into slot i of `out`.
void describe_image(const RgbImage& image, Descriptors ds, const SimilarityConfig& c, std::size_t i, Described& out) {
  for (std::size_t k = 0; k < ds.size(); ++k) {
    if (ds[k] == Descriptor::joint_histogram) {
      out.sets[k].sparse[i] = joint_histogram(image, c.joint_histogram);
    } else {
      const std::vector<float> v = dense_descriptor(image, ds[k], c);
      std::copy(v.begin(), v.end(), out.sets[k].dense.row(i).begin());
    }
  }
}

void prepare_slots(Described& out, Descriptors ds, std::size_t n, const SimilarityConfig& c) {
  out.sets.resize(ds.size());
  for (std::size_t k = 0; k < ds.size(); ++k) {
    if (ds[k] == Descriptor::joint_histogram) {
      out.sets[k].sparse.resize(n);
    } else {
      out.sets[k].dense = DenseMatrix<float>(n, dense_dimension(ds[k], c));
    }
  }
}

// The names of the descriptors that resize every image, for the warning about images of different sizes.
std::string resizing_names(Descriptors ds) {
  std::string names;
  for (Descriptor d : ds) names += (names.empty() ? "" : ", ") + std::string(descriptor_name(d));
  return names;
}

// Runs describe(i) for i in [0, n) on the configured threads; the error of the lowest failing index is
// rethrown, so the message does not depend on the thread count.
template <typename F>
void parallel_items(std::size_t n, unsigned threads, F&& describe) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<bool> failed{false};
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(static_cast <int>(threads))
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    if (failed.load(std::memory_order_relaxed)) continue;
    try {
      describe(static_cast<std::size_t>(k));
    } catch (...) {
      errors[static_cast<std::size_t>(k)] = std::current_exception();
      failed = true;
    }
  }
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

// Images of different sizes: an error for the joint histogram (its fixed 3x3 and 5x5 windows would see
// another scale in each), a warning for the descriptors that resize every image (patch, panorama).
void check_sizes(const std::vector<std::pair<int, int>>& sizes, const std::vector<std::string>& names,
                 const std::vector<fs::path>& files, Descriptors ds, const SimilarityConfig& c) {
  for (std::size_t k = 1; k < sizes.size(); ++k) {
    if (sizes[k] == sizes[0]) continue;
    const std::string what = std::to_string(sizes[k].first) + " x " + std::to_string(sizes[k].second) +
                             " pixels, the first image " + names[0] + " is " + std::to_string(sizes[0].first) + " x " +
                             std::to_string(sizes[0].second);
    if (has_joint_histogram(ds)) {
      throw InputError(files[k].string(),
                       "is " + what +
                           ": the joint-histogram descriptor does not resize (its 3x3 and 5x5 windows would see "
                           "a different scale in each); give images of one size, or --descriptor patch");
    }
    if (c.note) {
      c.note("warning: images of different sizes (" + names[k] + " is " + what + "); the " + resizing_names(ds) +
             " descriptor resizes every image");
    }
    return;
  }
}

void warn_skipped(const Source& s, const SimilarityConfig& c) {
  if (s.skipped.empty() || !c.note) return;
  std::string list;
  for (const auto& [path, why] : s.skipped) list += (list.empty() ? "" : "; ") + path.string() + " (" + why + ")";
  c.note("warning: --skip-unreadable left out " + std::to_string(s.skipped.size()) + " unreadable entries of " +
         s.input.path.string() + ": " + list);
}

Described describe_images(const Source& s, Descriptors ds, const SimilarityConfig& c) {
  Described out;
  const std::size_t n = s.images.size();
  prepare_slots(out, ds, n, c);
  out.names.reserve(n);
  for (const auto& p : s.images) out.names.push_back(image_name(s.input.path, p, s.input.recursive));
  warn_skipped(s, c);
  std::vector<std::pair<int, int>> sizes(n);
  out.entropy.resize(n);
  std::atomic<std::size_t> done{0};
  std::mutex report;
  parallel_items(n, thread_count(c.threads), [&](std::size_t i) {
    const fs::path& path = s.images[i];
    const RgbImage image = load_image(path);
    sizes[i] = {image.width, image.height};
    out.entropy[i] = significance::grey_entropy(image);
    if (c.on_image) c.on_image(i, image);
    try {
      describe_image(image, ds, c, i, out);
    } catch (const std::invalid_argument& e) {
      throw InputError(path.string(), e.what());
    }
    const std::size_t now = ++done;
    if (c.progress) {
      const std::lock_guard lock(report);
      c.progress("descriptors", now, n);
    }
  });
  check_sizes(sizes, out.names, s.images, ds, c);
  if (!sizes.empty()) out.size = sizes.front();
  return out;
}

// The frames of a video or a bag, in order: produce(visit) calls visit(name, image) once per kept frame.
using FrameProducer = std::function<void(const std::function<void(std::string, const RgbImage&)>&)>;

Described describe_stream(const Source& s, Descriptors ds, const SimilarityConfig& c, const FrameProducer& produce);

Described describe_video(const Source& s, Descriptors ds, const SimilarityConfig& c) {
  return describe_stream(s, ds, c, [&](const std::function<void(std::string, const RgbImage&)>& visit) {
    std::size_t next = 0;
    const auto& frames = s.input.frames;
    const auto read = for_each_video_frame(s.input.path, s.input.every, [&](std::size_t index, const RgbImage& frame) {
      if (!frames.empty()) {
        if (next >= frames.size() || frames[next] != index / s.input.every) return;
        ++next;
      }
      visit("frame " + std::to_string(index), frame);
    });
    if (const std::string warning = image::video_ended_early(s.input.path, read); !warning.empty() && c.note) {
      c.note(warning);
    }
    if (next < frames.size()) {
      throw InputError(s.input.path.string(),
                       "frame " + std::to_string(frames[next]) + " was selected, but the video has fewer frames");
    }
  });
}

Described describe_bag(const Source& s, Descriptors ds, const SimilarityConfig& c) {
#ifdef SEQTOPO_HAVE_RECORDING
  const recording::Recording bag(s.input.path);
  if (!s.unlisted.empty() && c.note) {
    std::string list;
    for (const auto& f : s.unlisted) list += (list.empty() ? "" : ", ") + f.filename().string();
    c.note("note: " + s.input.path.string() + ": not read, as its metadata.yaml does not list them: " + list);
  }
  return describe_stream(s, ds, c, [&](const std::function<void(std::string, const RgbImage&)>& visit) {
    bag.for_each_image(s.image_topic, s.input.every, s.input.frames,
                       [&](std::size_t index, double, const RgbImage& image) {
                         visit(s.image_topic + " " + std::to_string(index), image);
                       });
  });
#else
  (void)ds;
  (void)c;
  throw InputError(s.input.path.string(), "this seqtopo was built without bag support");
#endif
}

Described describe_stream(const Source& s, Descriptors ds, const SimilarityConfig& c, const FrameProducer& produce) {
  // Frames are decoded in order and described in batches, so a long video never sits in memory whole.
  Described out;
  std::vector<RgbImage> batch;
  std::vector<std::string> indices;
  const unsigned threads = thread_count(c.threads);
  const std::size_t batch_size = 8 * static_cast<std::size_t>(threads);
  std::vector<std::vector<similarity::SparseHistogram>> histograms(ds.size());
  std::vector<std::vector<std::vector<float>>> rows(ds.size());
  std::size_t described = 0;
  auto flush = [&] {
    for (std::size_t k = 0; k < ds.size(); ++k) {
      if (ds[k] == Descriptor::joint_histogram) {
        histograms[k].resize(described + batch.size());
      } else {
        rows[k].resize(described + batch.size());
      }
    }
    out.entropy.resize(described + batch.size());
    parallel_items(batch.size(), threads, [&](std::size_t b) {
      out.entropy[described + b] = significance::grey_entropy(batch[b]);
      try {
        for (std::size_t k = 0; k < ds.size(); ++k) {
          if (ds[k] == Descriptor::joint_histogram) {
            histograms[k][described + b] = joint_histogram(batch[b], c.joint_histogram);
          } else {
            rows[k][described + b] = dense_descriptor(batch[b], ds[k], c);
          }
        }
      } catch (const std::invalid_argument& e) {
        throw InputError(s.input.path.string(), indices[b] + ": " + e.what());
      }
    });
    described += batch.size();
    for (auto& name : indices) out.names.push_back(std::move(name));
    batch.clear();
    indices.clear();
    if (c.progress) c.progress("descriptors", out.names.size(), s.count.value_or(out.names.size()));
  };
  std::optional<std::pair<int, int>> first_size;
  bool size_warned = false;
  produce([&](std::string name, const RgbImage& frame) {
    if (!first_size) {
      first_size = std::pair{frame.width, frame.height};
    } else if (*first_size != std::pair{frame.width, frame.height} && !size_warned) {
      const std::string what = name + " is " + std::to_string(frame.width) + " x " + std::to_string(frame.height) +
                               " pixels, the first frame " + std::to_string(first_size->first) + " x " +
                               std::to_string(first_size->second);
      if (has_joint_histogram(ds)) {
        throw InputError(s.input.path.string(), what + ": the joint-histogram descriptor does not resize");
      }
      if (c.note) {
        c.note("warning: frames of different sizes (" + what + "); the " + resizing_names(ds) +
               " descriptor resizes every frame");
      }
      size_warned = true;
    }
    batch.push_back(frame);
    indices.push_back(std::move(name));
    if (batch.size() >= batch_size) flush();
  });
  if (!batch.empty()) flush();
  out.size = first_size;
  out.sets.resize(ds.size());
  for (std::size_t k = 0; k < ds.size(); ++k) {
    if (ds[k] == Descriptor::joint_histogram) {
      out.sets[k].sparse = std::move(histograms[k]);
      continue;
    }
    const std::size_t dim = dense_dimension(ds[k], c);
    out.sets[k].dense = DenseMatrix<float>(rows[k].size(), dim);
    for (std::size_t i = 0; i < rows[k].size(); ++i)
      std::copy(rows[k][i].begin(), rows[k][i].end(), out.sets[k].dense.row(i).begin());
  }
  return out;
}

DenseMatrix<float> kept_rows(DenseMatrix<float> all, const SequenceInput& input) {
  if (input.frames.empty()) return all;
  DenseMatrix<float> kept(input.frames.size(), all.cols);
  for (std::size_t r = 0; r < input.frames.size(); ++r) {
    if (input.frames[r] >= all.rows) {
      throw InputError(input.path.string(), "row " + std::to_string(input.frames[r]) +
                                                " was selected, but the array has " + std::to_string(all.rows) +
                                                " rows");
    }
    const auto row = all.row(input.frames[r]);
    std::copy(row.begin(), row.end(), kept.row(r).begin());
  }
  return kept;
}

std::vector<std::string> row_names(std::size_t n, const char* word) {
  std::vector<std::string> names;
  names.reserve(n);
  for (std::size_t i = 0; i < n; ++i) names.push_back(std::string(word) + " " + std::to_string(i));
  return names;
}

Described describe(const Source& s, Descriptors ds, const SimilarityConfig& c) {
  switch (s.kind) {
    case InputKind::images:
      return describe_images(s, ds, c);
    case InputKind::video:
      return describe_video(s, ds, c);
    case InputKind::bag:
      return describe_bag(s, ds, c);
    case InputKind::descriptors: {
      Described out;  // one set, the file's rows, whatever was asked (effective_descriptor)
      out.sets.push_back(similarity::DescriptorSet::from_dense(kept_rows(read_input_rows(s.input), s.input)));
      if (out.sets[0].dense.empty()) throw InputError(s.input.path.string(), "no descriptors (empty array)");
      out.names = row_names(out.sets[0].dense.rows, "row");
      return out;
    }
    default:
      break;
  }
  throw std::invalid_argument("internal: no descriptors for this input kind");
}

SimilarityResult from_similarity_file(const Source& s, bool square) {
  SimilarityResult r;
  r.similarity = io::read_npy_matrix<float>(s.input.path);
  if (r.similarity.empty()) throw InputError(s.input.path.string(), "empty similarity matrix");
  if (square && !r.similarity.square()) {
    throw InputError(s.input.path.string(), "similarity matrix of one sequence must be square, got " +
                                                std::to_string(r.similarity.rows) + " x " +
                                                std::to_string(r.similarity.cols));
  }
  r.kappa = std::numeric_limits<float>::quiet_NaN();
  r.frame_names = row_names(r.similarity.rows, "row");
  r.column_names = row_names(r.similarity.cols, "column");
  r.session_rows = {r.similarity.rows};
  return r;
}

// S = 1 - kappa D, with kappa given or chosen from the distances (symmetric: one sequence against itself).
void similarity_from(DenseMatrix<float> distances, bool symmetric, const SimilarityConfig& c, SimilarityResult& r) {
  if (c.kappa) {
    r.kappa = *c.kappa;
  } else {
    const auto choice = similarity::choose_kappa(distances, symmetric, c.kappa_rule);
    r.kappa = choice.kappa;
    r.kappa_auto = true;
    r.kappa_fraction = choice.fraction;
  }
  r.similarity = similarity::similarity_from_distance(std::move(distances), r.kappa);
}

void check_kappa(const SimilarityConfig& c) {
  if (c.kappa && (!(*c.kappa > 0) || !std::isfinite(*c.kappa))) throw std::invalid_argument("kappa must be positive");
}

// Several sessions of one side, resolved; the first one names the side in errors.
std::vector<Source> resolve_all(std::span<const SequenceInput> inputs) {
  if (inputs.empty()) throw std::invalid_argument("no input sequence");
  std::vector<Source> sources;
  for (const auto& input : inputs) sources.push_back(resolve(input));
  if (sources.size() > 1) {
    for (const auto& s : sources) {
      if (s.kind == InputKind::similarity) {
        throw InputError(s.input.path.string(),
                         "a similarity matrix cannot be one of several sessions (it has no rows for the others)");
      }
    }
  }
  return sources;
}

// One side's descriptors, session after session (names prefixed with the session's input when several).
Described describe_all(const std::vector<Source>& sources, Descriptors ds, const SimilarityConfig& c) {
  if (sources.size() == 1) {
    Described one = describe(sources.front(), ds, c);
    one.session_rows = {one.names.size()};
    return one;
  }
  Described all;
  all.sets.resize(ds.size());
  std::string first_input;
  for (const auto& s : sources) {
    SimilarityConfig session = c;  // on_image counts the rows of all the sessions
    if (c.on_image) {
      session.on_image = [&c, first = all.names.size()](std::size_t i, const RgbImage& image) {
        c.on_image(first + i, image);
      };
    }
    Described one = describe(s, ds, session);
    if (!all.size) {
      all.size = one.size;
      first_input = s.input.path.string();
    } else {
      check_same_size(all, first_input, one, s.input.path.string(), ds);
    }
    all.session_rows.push_back(one.names.size());
    all.entropy.insert(all.entropy.end(), one.entropy.begin(), one.entropy.end());
    const std::string prefix = s.input.path.filename().string() + "/";
    for (auto& name : one.names) all.names.push_back(prefix + name);
    for (std::size_t k = 0; k < ds.size(); ++k) {
      auto& to = all.sets[k];
      auto& from = one.sets[k];
      if (ds[k] == Descriptor::joint_histogram) {
        for (auto& h : from.sparse) to.sparse.push_back(std::move(h));
        continue;
      }
      if (!to.dense.empty() && to.dense.cols != from.dense.cols) {
        throw InputError(s.input.path.string(), "its descriptors have " + std::to_string(from.dense.cols) +
                                                    " columns, the first session's " + std::to_string(to.dense.cols));
      }
      to.dense.cols = from.dense.cols;
      to.dense.rows += from.dense.rows;
      to.dense.values.insert(to.dense.values.end(), from.dense.values.begin(), from.dense.values.end());
    }
  }
  return all;
}

// The side's sources as one for the memory estimate: the summed count (unknown when one is unknown).
Source combined(const std::vector<Source>& sources) {
  Source all = sources.front();
  std::size_t n = 0;
  for (const auto& s : sources) {
    if (!s.count) {
      all.count.reset();
      return all;
    }
    n += *s.count;
  }
  all.count = n;
  return all;
}

Descriptor side_descriptor(const std::vector<Source>& sources, const SimilarityConfig& c) {
  // effective_descriptor: c.descriptor, or npy for a descriptors.npy input
  const Descriptor d = effective_descriptor(sources.front(), c);
  for (const auto& s : sources) {
    if (effective_descriptor(s, c) != d) {
      throw InputError(s.input.path.string(), "every session must have the same kind of descriptor");
    }
  }
  return d;
}

// One matrix per descriptor in `requested` (c.descriptor is ignored), the images described in one pass.
std::vector<SimilarityResult> run(std::span<const SequenceInput> inputs_a, std::span<const SequenceInput> inputs_b,
                                  bool two, const SimilarityConfig& c, Descriptors requested) {
  check_kappa(c);
  if (requested.empty()) throw std::invalid_argument("no descriptor asked for");
  const std::vector<Source> a = resolve_all(inputs_a);
  if (a.front().kind == InputKind::similarity) return {from_similarity_file(a.front(), !two)};
  std::vector<Source> b;
  if (two) {
    b = resolve_all(inputs_b);
    for (const auto& s : b) {
      if (s.kind == InputKind::similarity) {
        throw InputError(s.input.path.string(), "a similarity matrix can only be the first input");
      }
    }
  }
  const Source all_a = combined(a);
  std::optional<Source> all_b;
  if (two) all_b = combined(b);
  std::vector<Descriptor> ds;
  for (Descriptor wanted : requested) {
    SimilarityConfig ck = c;
    ck.descriptor = wanted;
    const Descriptor d = side_descriptor(a, ck);
    if (two && side_descriptor(b, ck) != d) {
      throw InputError(b.front().input.path.string(), "both sequences must have the same kind of descriptor");
    }
    if (d == Descriptor::npy && requested.size() > 1) {
      throw InputError(all_a.input.path.string(), "a descriptors.npy input is one descriptor, not several");
    }
    check_memory(all_a, all_b ? &*all_b : nullptr, d, c);
    ds.push_back(d);
  }

  const auto t0 = Clock::now();
  Described da = describe_all(a, ds, c);
  std::optional<Described> db;
  if (two) {
    SimilarityConfig columns = c;
    columns.on_image = c.on_column_image;
    db = describe_all(b, ds, columns);
    check_same_size(da, a.front().input.path.string(), *db, b.front().input.path.string(), ds);
  }
  const double seconds_descriptors = seconds_since(t0);

  similarity::MatrixConfig mc;
  mc.threads = c.threads;
  mc.tile = c.tile;
  mc.memory_budget = available_memory_bytes();
  if (c.progress) mc.progress = [&c](std::size_t done, std::size_t total) { c.progress("matrix", done, total); };
  std::vector<SimilarityResult> results;
  for (std::size_t k = 0; k < ds.size(); ++k) {
    const Distance metric = c.distance.value_or(default_distance(ds[k]));
    SimilarityResult r;
    r.seconds_descriptors = k == 0 ? seconds_descriptors : 0.0;  // the one pass is counted once
    const auto t1 = Clock::now();
    // Descriptors of two lengths: the second sequence disagrees with the first, so it is the one named.
    if (db && !da.sets[k].is_sparse() && !db->sets[k].is_sparse() && da.sets[k].dense.cols != db->sets[k].dense.cols) {
      throw InputError(all_b->input.path.string(), "its descriptors have " + std::to_string(db->sets[k].dense.cols) +
                                                       " values, those of " + all_a.input.path.string() + " have " +
                                                       std::to_string(da.sets[k].dense.cols));
    }
    DenseMatrix<float> distances;
    try {
      distances = db ? similarity::distance_matrix(da.sets[k], db->sets[k], metric, mc)
                     : similarity::distance_matrix(da.sets[k], metric, mc);
    } catch (const similarity::MemoryError& e) {
      throw InputError(all_a.input.path.string(), e.what());
    } catch (const std::invalid_argument& e) {
      if (ds[k] == Descriptor::npy) throw InputError(all_a.input.path.string(), e.what());
      throw;
    }
    da.sets[k] = {};  // its descriptors are not needed any more
    if (db) db->sets[k] = {};
    similarity_from(std::move(distances), !db, c, r);
    r.seconds_matrix = seconds_since(t1);
    r.distance = metric;
    r.frame_names = da.names;
    r.column_names = db ? db->names : r.frame_names;
    r.session_rows = da.session_rows;
    // Every session's images, or none: a descriptors.npy session has no picture to measure.
    if (da.entropy.size() == r.frame_names.size()) r.frame_entropy = da.entropy;
    if (db && db->entropy.size() == r.column_names.size()) r.column_entropy = db->entropy;
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace

DescriptorResult compute_descriptors(std::span<const SequenceInput> inputs, const SimilarityConfig& config) {
  const std::vector<Source> sources = resolve_all(inputs);
  const Source& s = sources.front();
  if (s.kind == InputKind::similarity) {
    throw InputError(s.input.path.string(), "a similarity matrix has no descriptors");
  }
  const Descriptor d = side_descriptor(sources, config);
  if (d == Descriptor::joint_histogram) {
    throw InputError(s.input.path.string(), "the joint histogram is sparse and has no vector form");
  }
  DescriptorResult r;
  const auto t0 = Clock::now();
  Described described = describe_all(sources, std::span(&d, 1), config);
  r.descriptors = std::move(described.sets[0].dense);
  if (r.descriptors.empty()) throw InputError(s.input.path.string(), "no images");
  r.descriptor = d;
  if (described.entropy.size() == described.names.size()) r.frame_entropy = std::move(described.entropy);
  r.frame_names = std::move(described.names);
  r.session_rows = std::move(described.session_rows);
  r.seconds_descriptors = seconds_since(t0);
  return r;
}

DescriptorResult compute_descriptors(const SequenceInput& input, const SimilarityConfig& config) {
  return compute_descriptors(std::span<const SequenceInput>(&input, 1), config);
}

SimilarityResult similarity_of_descriptors(const DenseMatrix<float>& a, const DenseMatrix<float>* b,
                                           const SimilarityConfig& c) {
  check_kappa(c);
  for (const auto* m : {&a, b}) {
    if (m == nullptr) continue;
    const char* name = m == &a ? "descriptors" : "against";
    if (m->empty()) throw std::invalid_argument(std::string(name) + ": no descriptors (empty array)");
    for (std::size_t k = 0; k < m->values.size(); ++k) {
      if (!std::isfinite(m->values[k])) {
        throw std::invalid_argument(std::string(name) + ": non-finite value at row " + std::to_string(k / m->cols) +
                                    ", column " + std::to_string(k % m->cols));
      }
    }
  }
  const std::size_t cols = b ? b->rows : a.rows;
  const std::size_t bytes =
      similarity::matrix_bytes(a.rows, cols) + (a.values.size() + (b ? b->values.size() : 0)) * sizeof(float);
  const auto available = available_memory_bytes();
  similarity::check_fits(
      bytes, available,
      "the " + std::to_string(a.rows) + " x " + std::to_string(cols) + " similarity matrix with its descriptors");
  const Distance metric = c.distance.value_or(default_distance(Descriptor::npy));
  similarity::MatrixConfig mc;
  mc.threads = c.threads;
  mc.tile = c.tile;
  mc.memory_budget = available;
  const auto set_a = similarity::DescriptorSet::from_dense(a);
  DenseMatrix<float> distances =
      b ? similarity::distance_matrix(set_a, similarity::DescriptorSet::from_dense(*b), metric, mc)
        : similarity::distance_matrix(set_a, metric, mc);
  SimilarityResult r;
  similarity_from(std::move(distances), b == nullptr, c, r);
  r.distance = metric;
  r.frame_names = row_names(a.rows, "row");
  r.column_names = b ? row_names(b->rows, "row") : r.frame_names;
  return r;
}

SimilarityResult compute_similarity(const SequenceInput& input, const SimilarityConfig& config) {
  return compute_similarity(std::span<const SequenceInput>(&input, 1), config);
}

SimilarityResult compute_similarity(const SequenceInput& a, const SequenceInput& b, const SimilarityConfig& config) {
  return compute_similarity(std::span<const SequenceInput>(&a, 1), std::span<const SequenceInput>(&b, 1), config);
}

SimilarityResult compute_similarity(std::span<const SequenceInput> sessions, const SimilarityConfig& config) {
  return std::move(run(sessions, {}, false, config, std::span(&config.descriptor, 1)).front());
}

SimilarityResult compute_similarity(std::span<const SequenceInput> a, std::span<const SequenceInput> b,
                                    const SimilarityConfig& config) {
  return std::move(run(a, b, true, config, std::span(&config.descriptor, 1)).front());
}

std::vector<SimilarityResult> compute_similarities(std::span<const SequenceInput> sessions,
                                                   std::span<const Descriptor> descriptors,
                                                   const SimilarityConfig& config) {
  return run(sessions, {}, false, config, descriptors);
}

std::vector<SimilarityResult> compute_similarities(std::span<const SequenceInput> a, std::span<const SequenceInput> b,
                                                   std::span<const Descriptor> descriptors,
                                                   const SimilarityConfig& config) {
  return run(a, b, true, config, descriptors);
}

}  // namespace seqtopo::pipeline
