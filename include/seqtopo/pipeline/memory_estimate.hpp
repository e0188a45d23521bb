#pragma once
// What a `seqtopo map` run will hold in memory, stage by stage, from the sizes alone (before any work), so
// that a run that cannot fit is refused with the figure and an option that would fit instead of being killed
// by the kernel half-way.
//
// Images are decoded and described first, one per thread of the description at once (image_work_bytes, from the
// images' headers: a folder of a few huge images is refused before any is decoded).
// The dense path (N images, D descriptors fused; F = 4 N^2 bytes, one float matrix):
//   similarity   the D similarity matrices, made one after another (D F), with the descriptors of the one
//                being made (or the .npy input read: its raw values and their float copy)
//   enhancement  mapping::alignment_scores: the D matrices, the fused sum (F) and the enhanced copy of the one
//                being added (F, symmetrised in place); one matrix: its enhanced copy, or with a window of 0 a copy (F)
//   alignment    the D matrices and the scores (F), with each pass of the engine: the exact engine's float
//                table and forbidden-cell bytes (5 N^2), the fast engine's int16 checkpoint rows and columns
//                (about N^2 / 8); forward and reverse run at once with more than one thread
//   baseline     with ground truth, the SeqSLAM-style baseline's contrast-enhanced copy (F) of each matrix in turn
//   outputs      the encoded similarity.npy / scores.npy (F each, one at a time), similarity.png (a sorted copy
//                F, grey levels N^2 bytes and a picture of at most 2048 x 2048), the JSON documents of map.json
//                and alignments.json (about 256 bytes an aligned pair; 2 N pairs assumed before the run, the
//                real count checked again after it: check_outputs_memory)
// An N x N ground-truth image (N^2 bytes) is held from the accuracy stage on. --streaming holds the normalised
// descriptors, the tile cache (3 bands of 256 x 256 floats) and the fast engine's passes instead; --sparse its
// candidates, their FAISS index and the sparse engine's storage (its candidates, component labels and the kept
// components' runs) instead of the fast engine's passes, and of the tile cache only the tiles the significance fit
// reads. Estimated from the streamed cosine, the frames per place hold the scores at 201 lags of every frame (8 bytes
// each): at 10^6 frames, --sparse's largest stage.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "seqtopo/pipeline/map_pipeline.hpp"

namespace seqtopo::pipeline {

// The sizes an estimate needs (all [bytes] unless said).
struct MapMemoryInput {
  std::size_t images = 0;  // N
  // Per similarity matrix (one per fused descriptor; one for a .npy input): the bytes its descriptors hold
  // while the matrix is made, and the bytes of reading the input (a .npy: raw values plus their float copy).
  std::vector<std::size_t> descriptor_bytes{0};
  std::size_t input_read_bytes = 0;
  bool similarity_input = false;  // the input is the N x N matrix (read: input_read_bytes, kept: F)
  std::size_t contrast_window = 10;
  bool fast_engine = false;
  bool reverse = true;
  unsigned threads = 1;         // worker threads (resolved: >= 1)
  bool baseline = false;        // ground truth given: the SeqSLAM-style baseline runs (dense path)
  std::size_t truth_bytes = 0;  // an N x N ground-truth image
  bool streaming = false;
  bool sparse = false;  // with streaming: --sparse, `neighbours` candidates per frame
  std::size_t neighbours = 10;
  std::size_t dimension = 0;  // --streaming: floats per descriptor
  // --streaming: the frames per place are estimated from the streamed cosine (place units, no scale given, no
  // odometry)
  bool place_from_similarity = false;
  std::size_t base_bytes = 0;  // the process before the run: code, libraries, what it read so far
  // Images: what decoding and describing them holds at once, each of the description's threads with one image (the
  // largest of the folder, from the images' headers): the file read, the decoded picture and its RGB copies, or the
  // RgbImage with the descriptors' temporaries.
  std::size_t image_work_bytes = 0;
};

struct MemoryStage {
  std::string name;
  std::size_t bytes = 0;  // held at the stage's peak, base included (SIZE_MAX: beyond addressing)
};

struct MapMemoryEstimate {
  std::vector<MemoryStage> stages;
  std::size_t peak = 0;
  std::string peak_stage;
};

// Pure: sizes in, bytes per stage out.
MapMemoryEstimate estimate_map_memory(const MapMemoryInput& input);

// The streamed similarity's tile cache [tiles] (scale::StreamingConfig::cache_tiles; 0: its own default, three
// bands of tiles, which the dense streamed engine reads). The sparse mode reads only the significance fit's tiles
// and the bands of the confidences' posteriors (a few tiles at a time), so its cache is held to what they need.
std::size_t streamed_cache_tiles(std::size_t images, bool sparse);

// The sizes of `request` with `images` images (reads the .npy header or the first image where needed).
MapMemoryInput map_memory_input(const MapRequest& request, InputKind kind, std::size_t images);

// Estimates the run, and refuses it (InputError naming the input) when its peak exceeds `available`: the message
// gives the figure and what would fit (--threads 1, --engine fast, --streaming, the sparse mode). Returns the
// note to print ("memory estimate: ...").
std::string check_map_memory(const MapRequest& request, InputKind kind, std::size_t images,
                             std::optional<std::size_t> available);

// What writing a run's outputs adds to what the run holds: one encoded .npy, similarity.png or the JSON
// documents of map.json and alignments.json (about 256 bytes an aligned pair), the largest of them [bytes].
std::size_t outputs_extra_bytes(std::size_t images, std::size_t aligned_pairs, bool streaming);
// After the run, when its pairs are known: refuses (InputError naming `folder`) to write outputs that would not
// fit in `available` (what is left beside the run), so that nothing is half written and the old set stays.
void check_outputs_memory(const MapRun& run, std::optional<std::size_t> available, const std::string& folder);

// This process's resident memory now (VmRSS) and its peak (VmHWM) [bytes]; 0 when unknown.
std::size_t resident_bytes();
std::size_t peak_resident_bytes();

}  // namespace seqtopo::pipeline
