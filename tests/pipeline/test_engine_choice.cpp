// pipeline::choose_engine: the engine of a map run with none asked for, against budgets around the estimated
// peaks of each engine (memory_estimate.hpp), and the settings that stream.
#include <gtest/gtest.h>

#include "common/temp_dir.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/engine_choice.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"

namespace seqtopo::pipeline {
namespace {

std::size_t peak(MapRequest request, std::size_t n, bool fast, bool streaming, bool sparse = false) {
  request.settings.map.engine = fast ? mapping::MapConfig::Engine::fast : mapping::MapConfig::Engine::exact;
  request.streaming = streaming;
  request.sparse = sparse;
  return estimate_map_memory(map_memory_input(request, InputKind::descriptors, n)).peak;
}

TEST(EngineChoice, CheapestInAccuracyThatFitsTheBudget) {
  test_support::TempDir dir;
  const std::size_t n = 20000;  // large enough that the tables, not the process, decide
  DenseMatrix<float> rows(n, 16, 1.0F);
  const auto file = dir.path / "d.npy";
  io::write_npy(file, rows);
  MapRequest request;
  request.input.path = file;
  const std::size_t exact = peak(request, n, false, false), fast = peak(request, n, true, false),
                    streamed = peak(request, n, true, true), sparse = peak(request, n, true, true, true);
  // The estimates include this process's resident memory, which moves a little between calls: margins of m.
  const std::size_t m = std::size_t{64} << 20;
  ASSERT_LT(4 * fast + 2 * m, 4 * exact);
  ASSERT_LT(2 * streamed + 2 * m, 4 * fast);
  ASSERT_LT(2 * sparse + 2 * m, 2 * streamed);
  const auto engine = [&](std::size_t budget) { return choose_engine(request, InputKind::descriptors, n, budget); };
  EXPECT_EQ(engine(4 * exact + m).engine, MapEngine::exact);
  EXPECT_EQ(engine(4 * exact - m).engine, MapEngine::fast);
  EXPECT_EQ(engine(4 * fast + m).engine, MapEngine::fast);
  EXPECT_EQ(engine(4 * fast - m).engine, MapEngine::streaming);
  EXPECT_EQ(engine(2 * streamed + m).engine, MapEngine::streaming);
  EXPECT_EQ(engine(2 * streamed - m).engine, MapEngine::sparse);
  EXPECT_EQ(engine(2 * sparse + m).engine, MapEngine::sparse);
  // Nothing fits: fast, and the memory check refuses the run with what would fit.
  EXPECT_EQ(engine(2 * sparse - m).engine, MapEngine::fast);
  EXPECT_EQ(choose_engine(request, InputKind::descriptors, n, std::nullopt).engine, MapEngine::exact);
  EXPECT_NE(engine(4 * fast - m).why.find("engine streaming: "), std::string::npos);

  // Settings that cannot stream stay on the matrix, and say why.
  MapRequest paper = request;
  paper.preset = "paper";
  const auto refused = choose_engine(paper, InputKind::descriptors, n, 4 * fast - m);
  EXPECT_EQ(refused.engine, MapEngine::fast);
  EXPECT_NE(refused.why.find("cannot stream"), std::string::npos);
  MapRequest chi2 = request;
  chi2.settings.similarity.distance = Distance::chi2;
  EXPECT_FALSE(streaming_obstacle(chi2, InputKind::descriptors).empty());
  EXPECT_FALSE(streaming_obstacle(request, InputKind::similarity).empty());
  EXPECT_TRUE(streaming_obstacle(request, InputKind::descriptors).empty());
}

TEST(EngineChoice, StreamingSettingsTakeOneVectorDescriptorByCosine) {
  MapSettings fused;  // joint-histogram,patch
  EXPECT_FALSE(streaming_settings(fused, InputKind::images).empty());
  ASSERT_EQ(fused.descriptors.size(), 1U);
  EXPECT_EQ(fused.descriptors.front(), Descriptor::patch);
  EXPECT_EQ(fused.similarity.distance, Distance::cosine);
  MapSettings panoramas;
  panoramas.descriptors = {Descriptor::joint_histogram, Descriptor::panorama};
  streaming_settings(panoramas, InputKind::images);
  EXPECT_EQ(panoramas.descriptors, std::vector<Descriptor>{Descriptor::panorama});
  // Already streamable: nothing to say.
  EXPECT_TRUE(streaming_settings(fused, InputKind::images).empty());
  MapRequest request;
  const auto note = apply_engine_choice(request, InputKind::images, {MapEngine::streaming, "engine streaming: x"});
  EXPECT_TRUE(request.streaming);
  EXPECT_FALSE(request.sparse);
  EXPECT_EQ(request.settings.map.engine, mapping::MapConfig::Engine::fast);
  apply_engine_choice(request, InputKind::images, {MapEngine::sparse, "engine sparse: x"});
  EXPECT_TRUE(request.streaming && request.sparse);
  EXPECT_EQ(note.rfind("engine streaming: x; images compared by the patch", 0), 0U) << note;
}

}  // namespace
}  // namespace seqtopo::pipeline
