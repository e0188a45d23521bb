#include "seqtopo/pipeline/memory_estimate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <thread>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/image/codecs.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/image/joint_histogram.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/similarity/memory.hpp"
#include "seqtopo/similarity/sparse_histogram.hpp"

namespace seqtopo::pipeline {
namespace {

constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();

// Saturating arithmetic: a size beyond addressing stays SIZE_MAX.
std::size_t add(std::size_t a, std::size_t b) { return a > kMax - b ? kMax : a + b; }
std::size_t mul(std::size_t a, std::size_t b) { return a != 0 && b > kMax / a ? kMax : a * b; }
std::size_t sum(std::initializer_list<std::size_t> terms) {
  std::size_t s = 0;
  for (const std::size_t t : terms) s = add(s, t);
  return s;
}

constexpr std::size_t kFastTile = 32;       // the fast engine's tile side (align/fast_kernels.hpp kTileSide)
constexpr std::size_t kStreamTile = 256;    // StreamingConfig::tile
constexpr std::size_t kPictureSide = 2048;  // the largest similarity.png / overview [pixels]

// One pass of the exact engine (align/smith_waterman.cpp): the (N+1)^2 float table, the N^2 forbidden-cell
// bytes, each row's best and the row buffer.
std::size_t exact_pass(std::size_t n) { return sum({mul(mul(n + 1, n + 1), 4), mul(n, n), mul(n + 1, 8), mul(n, 4)}); }

// One pass of the fast engine (align/fast_alignment.cpp): int16 checkpoint rows every 32 rows, column
// checkpoints every 32 columns, the tiles' maxima, and the row ring and scratch rows of its threads.
std::size_t fast_pass(std::size_t n, unsigned threads) {
  const std::size_t stride = n + 1 + 64, bands = n / kFastTile + 1;
  return sum({mul(mul(bands, stride), 2), mul(mul(n + 1, n / kFastTile + 1), 2), mul(mul(bands, bands), 2),
              mul(mul(64 + 4, stride), 2 * static_cast<std::size_t>(std::max(1U, threads))), mul(n, 16)});
}

// The engine's passes held at once: forward and reverse run concurrently with more than one thread.
std::size_t engine_bytes(const MapMemoryInput& in) {
  const unsigned threads = std::max(1U, in.threads);
  const bool concurrent = in.reverse && threads > 1;
  const unsigned per_pass = concurrent ? std::max(1U, threads / 2) : threads;
  const std::size_t pass = in.fast_engine ? fast_pass(in.images, per_pass) : exact_pass(in.images);
  return mul(pass, concurrent ? 2 : 1);
}

// The fast engine traces an alignment back in a window of int16 values and scores (4 bytes a cell) that doubles
// from 32 until it holds the alignment's start, plus the step bits of its box: for an alignment over half the
// route (a route driven twice), about 2^k x N/2 cells with 2^k >= N/2 (align/fast_alignment.cpp recover()).
std::size_t traceback_window(std::size_t n) {
  const std::size_t length = n / 2;
  std::size_t reach = kFastTile;
  while (reach < length) reach *= 2;
  const std::size_t rows = std::min(n, reach + kFastTile), cols = std::min(reach, length + 1);
  return mul(mul(rows, cols), 5);
}

// The significance fit on a streamed source (mapping/map_builder.cpp fit_alignments()): the whole matrix up to 2 x
// kFitBlock frames, else kFitBlocks diagonal blocks of kFitBlock frames, each read into memory and aligned by the fast
// engine; the tile cache keeps the tiles read (a block off the tile grid straddles one more tile each way).
constexpr std::size_t kFitBlock = 2000, kFitBlocks = 4;

std::size_t fit_cache_tiles(std::size_t n, std::size_t capacity) {
  const bool whole = n <= 2 * kFitBlock;
  const std::size_t side = whole ? (n + kStreamTile - 1) / kStreamTile : kFitBlock / kStreamTile + 1;
  return std::min(capacity, mul(whole ? 1 : kFitBlocks, mul(side, side)));
}

// The bands of the confidences' posteriors (align/pair_posterior.hpp) move along a diagonal, a few tiles at a time.
constexpr std::size_t kBandTiles = 64;

// scale::StreamingSimilarity's own capacity: three bands of tiles.
std::size_t default_cache_tiles(std::size_t n) {
  return std::max<std::size_t>(4, mul(3, (n + kStreamTile - 1) / kStreamTile));
}

// mapping::estimate_frames_per_place from the streamed cosine: the scores at lags 0 .. min(200, N / 3) of every
// frame, or of evenly spaced frames above mapping::kPlaceScaleFrames, as floats (pipeline/map_pipeline.cpp,
// mapping/place_scale.cpp).
constexpr std::size_t kPlaceMaxLag = 200;
std::size_t place_scale_bytes(std::size_t n) {
  const std::size_t lags = std::min(kPlaceMaxLag, n / 3);
  return lags < 4 ? 0 : mul(mul(lags + 1, std::min(n, mapping::kPlaceScaleFrames)), sizeof(float));
}

// What the sparse engine stores (scale/sparse_alignment.hpp, sparse_components.hpp) [bytes]: per candidate cell its
// column and score in the candidates and in their copy minus the offset, the entry the copy is built from, and at
// most one component label (parent and slot); per row of a kept component its row offset and one run, and the run
// with its row while the component is open.
constexpr std::size_t kSparseCandidateBytes = 8, kSparseEntryBytes = 12, kSparseLabelBytes = 8, kSparseRowBytes = 32;

std::size_t sparse_engine_bytes(std::size_t images, std::size_t neighbours) {
  // Each frame's neighbours in both triangles: the candidate cells.
  const std::size_t candidates = mul(mul(images, neighbours), 2);
  // The candidates (column and score) and their copy minus the offset the engine aligns, built from entries.
  const std::size_t scores = mul(candidates, 2 * kSparseCandidateBytes + kSparseEntryBytes);
  // The two passes at once, each over one triangle: at most a component label (parent and slot) per candidate.
  const std::size_t labels = mul(candidates, kSparseLabelBytes);
  // The components kept, about one run a row of an aligned component (its row offset and the run, and the run while
  // the component is open); a route driven twice aligns about N rows a pass.
  const std::size_t runs = mul(mul(images, 2), kSparseRowBytes);
  return sum({scores, labels, runs});
}

// map.json and alignments.json are built as JSON documents, one after the other: about 256 bytes an aligned pair
// (formats/map_json.cpp). Before the run the pairs are not known: a route driven twice aligns about N.
constexpr std::size_t kJsonBytesPerPair = 256;

// The side of a picture of an N x N matrix: upscaled to at least 512, block means down to at most 2048.
std::size_t picture_side(std::size_t n) {
  if (n == 0) return 1;
  if (n < 512) return n * ((512 + n - 1) / n);
  return std::min(n, kPictureSide);
}

// A picture of an N x N matrix (plot/matrix_image.cpp, plot/png.cpp): inside matrix_image a sorted copy of the
// values, the grey levels, the scaled grey, RGB and the RgbImage; then the encoding: the image, BGR, the PNG bytes
// and their string.
std::size_t picture_bytes(std::size_t n) {
  const std::size_t side = picture_side(n), pixels = mul(side, side);
  return std::max(sum({mul(mul(n, n), 5), mul(pixels, 7)}), mul(pixels, 12));
}

// What describing one image holds besides its RgbImage (3 bytes a pixel) [bytes a pixel]: the joint histogram's
// feature planes (intensity, squared gradient, edge count, texturedness, rank, bin: 10) and its padded and edge
// planes (3) (image/joint_histogram.cpp); the patch thumbnail's float intensity (4) (image/patch_thumbnail.cpp); the
// panorama signature works on a small copy. The descriptors of an image are made one after the other.
std::size_t describe_bytes_per_pixel(const std::vector<Descriptor>& descriptors) {
  std::size_t most = 0;
  for (const Descriptor d : descriptors) {
    most = std::max<std::size_t>(most, d == Descriptor::joint_histogram ? 13 : d == Descriptor::patch ? 4 : 0);
  }
  return 3 + most;
}

// Images whose headers are read for the estimate: all of a folder up to this many, else as many evenly spaced.
constexpr std::size_t kHeaderSample = 512;

struct ImageWork {
  std::size_t per_image = 0;     // the most one image's decoding or describing holds [bytes]
  std::size_t first_pixels = 0;  // of the first image (0: unknown)
};

// From the images' headers, without decoding (image::read_image_header); an image of a format whose header is not
// read counts as the first one whose is, or (none) is decoded once to learn its size.
ImageWork image_work(const std::vector<std::filesystem::path>& files, const std::vector<Descriptor>& descriptors) {
  ImageWork w;
  if (files.empty()) return w;
  const std::size_t step = std::max<std::size_t>(1, (files.size() + kHeaderSample - 1) / kHeaderSample);
  const std::size_t per_pixel = describe_bytes_per_pixel(descriptors);
  std::optional<image::ImageHeader> known;
  std::vector<std::size_t> sample;
  for (std::size_t k = 0; k < files.size(); k += step) sample.push_back(k);
  if (sample.back() + 1 != files.size()) sample.push_back(files.size() - 1);
  for (const std::size_t k : sample) {
    std::error_code ec;
    const auto file_bytes = static_cast<std::size_t>(std::filesystem::file_size(files[k], ec));
    std::optional<image::ImageHeader> h = image::read_image_header(files[k]);
    if (!h && !known) {
      try {
        h = image::image_size(files[k]);
      } catch (const std::exception&) {
        // an unreadable image is reported by the run itself
      }
    }
    if (!h) h = known;
    if (!h) continue;
    known = h;
    const std::size_t pixels = mul(static_cast<std::size_t>(h->width), static_cast<std::size_t>(h->height));
    if (k == 0) w.first_pixels = pixels;
    w.per_image = std::max({w.per_image, image::decode_peak_bytes(*h, ec ? 0 : file_bytes), mul(pixels, per_pixel)});
  }
  return w;
}

}  // namespace

std::size_t outputs_extra_bytes(std::size_t images, std::size_t pairs, bool streaming) {
  const std::size_t json = mul(pairs, kJsonBytesPerPair);
  if (streaming) {
    const std::size_t block = std::max<std::size_t>(1, (images + kPictureSide - 1) / kPictureSide);
    return std::max(picture_bytes((images + block - 1) / block), json);
  }
  return std::max({add(mul(mul(images, images), 4), 128), picture_bytes(images), json});
}

std::size_t streamed_cache_tiles(std::size_t images, bool sparse) {
  if (!sparse) return 0;
  return std::min(default_cache_tiles(images), add(fit_cache_tiles(images, default_cache_tiles(images)), kBandTiles));
}

MapMemoryEstimate estimate_map_memory(const MapMemoryInput& in) {
  MapMemoryEstimate e;
  const std::size_t n = in.images;
  const std::size_t f = mul(mul(n, n), 4);  // one N x N float matrix
  const std::size_t base = in.base_bytes;
  const auto stage = [&](std::string name, std::size_t bytes) {
    e.stages.push_back({std::move(name), add(base, bytes)});
  };

  if (in.streaming) {
    const std::size_t descriptors = mul(mul(n, in.dimension), 4);
    const std::size_t cache = mul(default_cache_tiles(n), kStreamTile * kStreamTile * 4);
    // a thread's tile: the raw tile widened by the window, the tile and its window sums
    const std::size_t wide = kStreamTile + 2 * in.contrast_window;
    const std::size_t tile_work =
        mul(std::max(1U, in.threads), sum({mul(mul(wide, wide), 4), kStreamTile * kStreamTile * 4, kStreamTile * 40}));
    // the overview of at most 2048 x 2048 block maxima (plot/matrix_overview.hpp)
    const std::size_t block = std::max<std::size_t>(1, (n + kPictureSide - 1) / kPictureSide);
    const std::size_t side = (n + block - 1) / block;
    const std::size_t overview = mul(mul(side, side), 4);
    // The sparse mode aligns its candidates instead of every pair (sparse_engine_bytes), beside the streamed
    // similarity's descriptors and their transpose, the FAISS index (another copy) and its search results (12 bytes
    // a neighbour) and the overview's block counts. The streamed scores are read by the significance fit and the
    // confidences only, through a cache held to their tiles (streamed_cache_tiles); the fit's block and its fast
    // engine come and go before the sparse engine runs.
    MapMemoryInput fit_block = in;
    fit_block.images = n <= 2 * kFitBlock ? n : kFitBlock;
    fit_block.fast_engine = true;
    const std::size_t fit = sum(
        {mul(mul(fit_block.images, fit_block.images), 4), engine_bytes(fit_block), traceback_window(fit_block.images)});
    const std::size_t fit_cache = mul(streamed_cache_tiles(n, true), kStreamTile * kStreamTile * 4);
    const std::size_t sparse =
        sum({mul(descriptors, 2), fit_cache, mul(mul(n, in.neighbours), 12),
             std::max(fit, sparse_engine_bytes(n, in.neighbours)), mul(kPictureSide * kPictureSide, 8)});
    const std::size_t aligned = in.sparse ? sum({descriptors, tile_work, sparse})
                                          : sum({descriptors, cache, tile_work, engine_bytes(in), traceback_window(n)});
    // the descriptors read, then normalised by the streamed similarity (the descriptors and their transpose), which
    // the frames per place are estimated from unless given
    const std::size_t described = add(descriptors, in.descriptor_bytes.empty() ? 0 : in.descriptor_bytes.front());
    stage("descriptors",
          std::max({in.input_read_bytes, add(described, in.image_work_bytes),
                    in.place_from_similarity ? sum({described, descriptors, place_scale_bytes(n)}) : described}));
    stage("alignment (streamed)", aligned);
    // what the alignment's threads freed mostly stays with the process (their heaps): counted on
    stage("similarity overview", add(aligned, overview));
    stage("outputs",
          sum({aligned, overview, in.truth_bytes, std::max(picture_bytes(side), mul(mul(n, 2), kJsonBytesPerPair))}));
  } else {
    const std::size_t d = std::max<std::size_t>(1, in.descriptor_bytes.size());
    // 1. the matrices, one after another: the k-th is made while the others are held, beside its descriptors
    // 0. the images decoded and described, on the description's threads at once, beside the descriptors made
    std::size_t described = in.image_work_bytes;
    for (const std::size_t bytes : in.descriptor_bytes) described = add(described, bytes);
    std::size_t similarity = std::max(in.input_read_bytes, in.image_work_bytes == 0 ? 0 : described);
    if (in.similarity_input) {
      similarity = std::max(similarity, f);
    } else {
      for (std::size_t k = 0; k < d; ++k) {
        similarity = std::max(similarity, sum({mul(k + 1, f), in.descriptor_bytes[k]}));
      }
    }
    stage("similarity", similarity);
    // 2. alignment_scores
    const std::size_t matrices = mul(d, f);
    // One matrix: its enhanced copy (symmetrised in place) or, with a window of 0, a plain copy; several: the
    // fused sum and the enhanced copy of the one being added.
    const std::size_t enhancement = add(matrices, mul(d == 1 ? 1 : 2, f));
    stage("contrast enhancement", enhancement);
    // 3. the alignment, with the scores beside the matrices
    const std::size_t held = add(matrices, f);
    stage("alignment", sum({held, engine_bytes(in), in.fast_engine ? traceback_window(n) : 0}));
    // 4. accuracy: the ground-truth image (read: twice), the baseline's enhanced copy
    const std::size_t truth = in.truth_bytes;
    stage("accuracy", sum({held, mul(truth, 2), in.baseline ? f : 0}));
    // 5. outputs: one encoded .npy or similarity.png at a time
    stage("outputs", sum({held, truth, outputs_extra_bytes(n, mul(n, 2), false)}));
  }
  for (const auto& s : e.stages) {
    if (s.bytes > e.peak || e.peak_stage.empty()) {
      e.peak = s.bytes;
      e.peak_stage = s.name;
    }
  }
  return e;
}

MapMemoryInput map_memory_input(const MapRequest& request, InputKind kind, std::size_t images) {
  const MapSettings& s = request.settings;
  if (request.sessions.empty()) throw std::invalid_argument("map_memory_input: no session");
  const SequenceInput& input = request.sessions.front().input;
  MapMemoryInput in;
  in.images = images;
  in.contrast_window = s.map.score.contrast_window;
  in.fast_engine = s.map.engine == mapping::MapConfig::Engine::fast;
  in.reverse = s.map.search.reverse;
  const unsigned cores = std::max(1U, std::thread::hardware_concurrency());
  in.threads = s.map.threads == 0 ? cores : s.map.threads;
  if (!in.fast_engine && s.map.threads == 0) in.threads = 1;  // the exact engine's passes: concurrent only if > 1
  in.streaming = streams(request.engine);
  in.sparse = request.engine == MapEngine::sparse;
  in.neighbours = request.sparse.neighbours.value_or(SparseOptions::kDefaultNeighbours);
  const bool odometry = std::any_of(request.sessions.begin(), request.sessions.end(),
                                    [](const SessionSource& session) { return !session.odometry.empty(); });
  in.place_from_similarity = (s.map.unit == align::Unit::places) && !s.map.frames_per_place && !odometry;
  // A video's run, or a folder of images other than PNG and JPEG, opens OpenCV's codecs plugin, whose libraries
  // (~80 MB resident) are part of the process it will be. PNG and JPEG (frames, figures) need no plugin.
  bool plugin = kind == InputKind::video;
  for (const auto& session : request.sessions) {
    if (plugin || kind != InputKind::images) break;
    const auto files = list_input_images(session.input).files;
    plugin = !std::all_of(files.begin(), files.end(), image::codecs::read_without_plugin);
  }
  if (plugin) image::codecs::load();
  in.base_bytes = resident_bytes();
  const std::filesystem::path& truth = request.truth.same_place;
  in.baseline = !truth.empty() && !in.streaming;
  if (!truth.empty() && truth.extension() != ".csv") in.truth_bytes = mul(images, images);

  if (kind == InputKind::descriptors || kind == InputKind::similarity) {
    const auto header = io::read_npy_header(input.path);
    std::size_t count = 1;
    for (const std::size_t extent : header.shape) count = mul(count, extent);
    // The float copy, and the raw values read in blocks of 2^16 (io/npy.cpp).
    in.input_read_bytes = mul(count, 4) + mul(std::min<std::size_t>(count, 1 << 16), header.item);
    const std::size_t cols = header.shape.size() == 2 ? header.shape[1] : 0;
    in.similarity_input = kind == InputKind::similarity;
    in.descriptor_bytes = {in.similarity_input ? 0 : mul(mul(images, cols), 4)};
    in.dimension = cols;
    return in;
  }
  // Images or a video: each descriptor's vectors (a joint histogram keeps at most one bin per pixel of the first
  // image, every bin for a video).
  std::vector<Descriptor> descriptors = s.descriptors;
  if (descriptors.empty()) descriptors = {Descriptor::joint_histogram};
  if (in.streaming) descriptors.resize(1);
  std::size_t pixels = image::JointHistogramConfig::bins;
  if (kind == InputKind::images) {
    const auto files = list_input_images(input).files;
    const ImageWork work = image_work(files, descriptors);
    if (work.first_pixels) pixels = work.first_pixels;
    const std::size_t threads = std::min<std::size_t>(std::max<std::size_t>(1, images),
                                                      s.similarity.threads == 0 ? cores : s.similarity.threads);
    in.image_work_bytes = mul(work.per_image, threads);
  } else if (kind == InputKind::video) {
    // Frames are decoded in order and described in batches of 8 a thread (sequence_similarity.cpp): the batch's
    // RgbImages, the decoder's frame and its RGB conversion, and each thread's describing temporaries.
    if (const auto header = image::video_frame_header(input.path)) {
      const std::size_t frame = mul(static_cast<std::size_t>(header->width), static_cast<std::size_t>(header->height));
      const std::size_t threads = s.similarity.threads == 0 ? cores : s.similarity.threads;
      in.image_work_bytes = sum({mul(mul(8 * threads, 3), frame), mul(frame, 2 * 3),
                                 mul(mul(threads, describe_bytes_per_pixel(descriptors) - 3), frame)});
    }
  }
  in.descriptor_bytes.clear();
  for (const Descriptor d : descriptors) {
    std::size_t per_image = 0;
    if (d == Descriptor::joint_histogram) {
      const std::size_t bins = std::min<std::size_t>(image::JointHistogramConfig::bins, pixels);
      per_image = sizeof(similarity::SparseHistogram) + bins * (sizeof(std::uint32_t) + sizeof(float));
    } else if (d == Descriptor::patch) {
      per_image = static_cast<std::size_t>(std::max(0, s.similarity.patch.width)) *
                  static_cast<std::size_t>(std::max(0, s.similarity.patch.height)) * sizeof(float);
      in.dimension = per_image / sizeof(float);
    } else if (d == Descriptor::panorama) {
      per_image = s.similarity.panorama.dimension() * sizeof(float);
      in.dimension = per_image / sizeof(float);
    }
    in.descriptor_bytes.push_back(mul(images, per_image));
  }
  return in;
}

std::string check_map_memory(const MapRequest& request, InputKind kind, std::size_t images,
                             std::optional<std::size_t> available) {
  const MapMemoryInput in = map_memory_input(request, kind, images);
  const MapMemoryEstimate e = estimate_map_memory(in);
  const auto text = [](std::size_t bytes) {
    return bytes == kMax ? std::string("more than can be addressed") : similarity::format_bytes(bytes);
  };
  const std::string figure =
      fmt::format("the map of {} images needs about {} at its peak ({})", images, text(e.peak), e.peak_stage);
  if (!available || e.peak <= *available) {
    return "memory estimate: " + figure +
           (available ? ", " + similarity::format_bytes(*available) + " available" : std::string());
  }
  // What would fit instead, cheapest change first.
  std::vector<std::string> fits;
  const auto consider = [&](const std::string& change, MapMemoryInput alternative) {
    const auto peak = estimate_map_memory(alternative).peak;
    if (peak <= *available) fits.push_back(fmt::format("{} (about {})", change, text(peak)));
  };
  if (!in.streaming) {
    if (in.threads > 1 && in.reverse) {
      MapMemoryInput one = in;
      one.threads = 1;
      consider("--threads 1 (one alignment pass at a time)", one);
    }
    if (!in.fast_engine) {
      MapMemoryInput fast = in;
      fast.fast_engine = true;
      consider("--engine fast (no N x N alignment table)", fast);
    }
    if (!in.similarity_input) {
      MapMemoryInput streamed = in;
      streamed.streaming = true;
      streamed.fast_engine = true;
      streamed.baseline = false;
      streamed.descriptor_bytes.resize(1);
      consider(kind == InputKind::descriptors ? "--streaming (never the N x N matrix)"
                                              : "--streaming (one vector descriptor by cosine; never the N x N "
                                                "matrix)",
               streamed);
      MapMemoryInput sparse = streamed;
      sparse.sparse = true;
      consider("--sparse (each frame's nearest neighbours only)", sparse);
    }
  }
  std::string advice = fits.empty() ? "nothing of --threads 1, --engine fast, --streaming or --sparse fits either"
                                    : "it would fit with " + fits.front();
  for (std::size_t k = 1; k < fits.size(); ++k) advice += ", or " + fits[k];
  throw InputError(request.sessions.front().input.path.string(),
                   figure + ", only " + similarity::format_bytes(*available) + " of memory is available; " + advice);
}

void check_outputs_memory(const MapRun& run, std::optional<std::size_t> available, const std::string& folder) {
  if (!available) return;
  std::size_t pairs = 0;
  for (const auto& a : run.result.alignments) pairs = add(pairs, a.pairs.size());
  for (const auto& a : run.result.rejected) pairs = add(pairs, a.pairs.size());
  const std::size_t need = outputs_extra_bytes(run.result.map.labels.size(), pairs, run.streamed());
  if (need > *available) {
    throw InputError(folder, fmt::format("writing the outputs ({} aligned pairs) needs about {} more, only {} of "
                                         "memory is available; nothing was written",
                                         pairs, similarity::format_bytes(need), similarity::format_bytes(*available)));
  }
}

namespace {
std::size_t status_kib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string word;
  while (in >> word) {
    if (word == key) {
      std::size_t kib = 0;
      in >> kib;
      return kib * 1024;
    }
  }
  return 0;
}
}  // namespace

std::size_t resident_bytes() { return status_kib("VmRSS:"); }
std::size_t peak_resident_bytes() { return status_kib("VmHWM:"); }

}  // namespace seqtopo::pipeline
