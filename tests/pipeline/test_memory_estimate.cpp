// pipeline::estimate_map_memory: the stages of a map run from its sizes (the measured peaks are in
// tests/cli/test_memory_estimate.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/mapping/place_scale.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"
#include "seqtopo/scale/sparse_alignment.hpp"
#include "seqtopo/scale/sparse_components.hpp"

namespace seqtopo::pipeline {
namespace {

std::size_t stage(const MapMemoryEstimate& e, const std::string& name) {
  for (const auto& s : e.stages) {
    if (s.name == name) return s.bytes;
  }
  ADD_FAILURE() << "no stage " << name;
  return 0;
}

MapMemoryInput dense(std::size_t n) {
  MapMemoryInput in;
  in.images = n;
  in.threads = 2;
  return in;
}

TEST(EstimateMapMemory, DenseStagesCountEveryMatrix) {
  const std::size_t n = 10000, f = n * n * 4;
  const auto e = estimate_map_memory(dense(n));
  // one matrix and its enhanced copy (symmetrised in place)
  EXPECT_EQ(stage(e, "contrast enhancement"), 2 * f);
  // the matrix, the scores, and two concurrent passes of the exact engine (float table and forbidden bytes)
  EXPECT_GE(stage(e, "alignment"), 2 * f + 2 * (5 * n * n));
  EXPECT_LT(stage(e, "alignment"), 2 * f + 2 * (5 * n * n) + f / 100);
  EXPECT_EQ(e.peak_stage, "alignment");
  EXPECT_EQ(e.peak, stage(e, "alignment"));
  // two fused descriptors: both matrices, the sum and the enhanced copy being added
  MapMemoryInput two = dense(n);
  two.descriptor_bytes = {0, 0};
  EXPECT_EQ(stage(estimate_map_memory(two), "contrast enhancement"), 4 * f);
  // the process's own memory is added to every stage
  MapMemoryInput based = dense(n);
  based.base_bytes = 12345;
  EXPECT_EQ(estimate_map_memory(based).peak, e.peak + 12345);
}

TEST(EstimateMapMemory, CheaperPathsAreCheaper) {
  const std::size_t n = 20000;
  const auto exact2 = estimate_map_memory(dense(n)).peak;
  MapMemoryInput one = dense(n);
  one.threads = 1;
  MapMemoryInput fast = dense(n);
  fast.fast_engine = true;
  MapMemoryInput streamed = dense(n);
  streamed.streaming = true;
  streamed.fast_engine = true;
  streamed.dimension = 64;
  const auto one_peak = estimate_map_memory(one).peak, fast_peak = estimate_map_memory(fast).peak,
             streamed_peak = estimate_map_memory(streamed).peak;
  EXPECT_LT(one_peak, exact2);
  EXPECT_LE(fast_peak, one_peak);  // both at the outputs stage: the matrices and the picture
  EXPECT_LT(stage(estimate_map_memory(fast), "alignment"), stage(estimate_map_memory(one), "alignment"));
  EXPECT_LT(streamed_peak, fast_peak / 2);
  // no reverse pass: one table whatever the threads
  MapMemoryInput forward = dense(n);
  forward.reverse = false;
  EXPECT_EQ(estimate_map_memory(forward).peak, one_peak);
}

TEST(EstimateMapMemory, GrowsWithTheImagesAndSaturates) {
  std::size_t previous = 0;
  for (std::size_t n : {10, 100, 1000, 10000, 100000}) {
    const auto peak = estimate_map_memory(dense(n)).peak;
    EXPECT_GT(peak, previous);
    previous = peak;
  }
  const auto huge = estimate_map_memory(dense(std::size_t{1} << 40));
  EXPECT_EQ(huge.peak, std::numeric_limits<std::size_t>::max()) << "beyond addressing, not wrapped";
}

TEST(EstimateMapMemory, GroundTruthAndTheBaseline) {
  const std::size_t n = 5000, f = n * n * 4;
  MapMemoryInput in = dense(n);
  const auto without = stage(estimate_map_memory(in), "accuracy");
  in.baseline = true;
  in.truth_bytes = n * n;
  const auto with = stage(estimate_map_memory(in), "accuracy");
  EXPECT_EQ(with, without + f + 2 * n * n);
}

MapMemoryInput sparse(std::size_t n, std::size_t neighbours) {
  MapMemoryInput in;
  in.images = n;
  in.threads = 2;
  in.streaming = true;
  in.fast_engine = true;
  in.sparse = true;
  in.neighbours = neighbours;
  in.dimension = 64;
  return in;
}

// The sparse mode's alignment stage grows with what the code stores per frame and neighbour, and per frame; neither
// the fill's positive cells (a few per candidate before it kept two rows) nor the tile cache's capacity (the sparse
// engine reads the candidates, only the significance fit reads streamed tiles) grow it.
TEST(EstimateMapMemory, SparseGrowsWithWhatTheSparseEngineStores) {
  // A frame's neighbour is a candidate cell in both triangles, each its column and score in the candidates and in
  // their copy minus the offset (SparseScores), the SparseEntry the copy is built from, and at most one component
  // label (union-find parent and slot); and FAISS's search result (distance and 64-bit label).
  const std::size_t per_candidate =
      2 * (sizeof(std::uint32_t) + sizeof(float)) + sizeof(scale::SparseEntry) + 2 * sizeof(std::uint32_t);
  const std::size_t per_neighbour = 2 * per_candidate + sizeof(float) + sizeof(std::int64_t);
  // A frame: the streamed similarity's descriptors and their transpose, FAISS's copy; in each of the two passes about
  // one row of a kept component: its row offset and run, and the run with its row while the component is open.
  const std::size_t dim = 64;
  const std::size_t per_frame = 3 * dim * sizeof(float) + 2 * (sizeof(std::size_t) + sizeof(scale::SparseRun) +
                                                               sizeof(std::size_t) + sizeof(scale::SparseRun));
  const auto aligned = [](std::size_t n, std::size_t k) {
    return stage(estimate_map_memory(sparse(n, k)), "alignment (streamed)");
  };
  for (const std::size_t n : {100000, 1000000}) {
    for (const std::size_t k : {5, 10, 20}) {
      EXPECT_EQ(aligned(n, 2 * k) - aligned(n, k), k * n * per_neighbour) << n << " frames, k = " << k;
      EXPECT_EQ(aligned(2 * n, k) - aligned(n, k), n * (k * per_neighbour + per_frame)) << n << " frames, k = " << k;
    }
  }
  // far below the streamed fast engine's, which holds the tile cache and the engine's passes
  MapMemoryInput streamed = sparse(1000000, 10);
  streamed.sparse = false;
  EXPECT_LT(aligned(1000000, 10) * 4, stage(estimate_map_memory(streamed), "alignment (streamed)"));
}

// Estimated from the streamed cosine, the frames per place hold min(200, N / 3) + 1 lags of every frame as doubles
// (each lag's vector grown by doubling), beside the descriptors read and the streamed copy and transpose of them.
TEST(EstimateMapMemory, PlaceScaleFromTheStreamedCosine) {
  for (const std::size_t n : {1000, 100000, 1000000}) {
    MapMemoryInput in = sparse(n, 10);
    const std::size_t d = n * 64 * sizeof(float);
    in.descriptor_bytes = {d};
    EXPECT_EQ(stage(estimate_map_memory(in), "descriptors"), 2 * d);
    in.place_from_similarity = true;
    const std::size_t lags = std::min<std::size_t>(200, n / 3) + 1;
    // The lags of every frame, or of evenly spaced frames above kPlaceScaleFrames, as floats (place_scale.hpp).
    const std::size_t frames = std::min(n, mapping::kPlaceScaleFrames);
    EXPECT_EQ(stage(estimate_map_memory(in), "descriptors"), 3 * d + lags * frames * sizeof(float)) << n;
  }
}

// After the run: the outputs of its real number of aligned pairs are checked against what is left, before any is
// written; the error names the output folder.
TEST(EstimateMapMemory, OutputsOfTheRunsPairs) {
  const std::size_t n = 3000;
  MapRun run;
  run.result.map.labels.resize(n);
  align::LocalAlignment a;
  for (std::size_t i = 0; i < 20000; ++i) a.pairs.emplace_back(i % n, i % n);
  run.result.alignments.push_back(a);
  run.result.rejected.push_back(a);
  const std::size_t need = outputs_extra_bytes(n, 40000, false);
  EXPECT_GE(need, std::size_t{4} * n * n) << "at least one encoded N x N .npy";
  EXPECT_GT(outputs_extra_bytes(n, 4000000, false), need) << "JSON of 4 million pairs outweighs the matrix";
  EXPECT_LT(outputs_extra_bytes(n, 40000, true), need) << "streaming writes no N x N matrix";
  EXPECT_NO_THROW(check_outputs_memory(run, std::nullopt, "out"));
  EXPECT_NO_THROW(check_outputs_memory(run, need, "out"));
  try {
    check_outputs_memory(run, need - 1, "out");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), "out");
    EXPECT_NE(std::string(e.what()).find("40000 aligned pairs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seqtopo::pipeline
