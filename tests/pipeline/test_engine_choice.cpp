// pipeline::choose_engine: the engine of a map run with none asked for, against budgets around the estimated
// peaks of each engine (memory_estimate.hpp), the settings that stream, and check_request's refusals.
#include <gtest/gtest.h>

#include "common/temp_dir.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/engine_choice.hpp"
#include "seqtopo/pipeline/memory_estimate.hpp"

namespace seqtopo::pipeline {
namespace {

std::size_t peak(MapRequest request, std::size_t n, MapEngine engine) {
  apply_engine(request, InputKind::descriptors, engine);
  return estimate_map_memory(map_memory_input(request, InputKind::descriptors, n)).peak;
}

TEST(EngineChoice, CheapestInAccuracyThatFitsTheBudget) {
  test_support::TempDir dir;
  const std::size_t n = 20000;  // large enough that the tables, not the process, decide
  DenseMatrix<float> rows(n, 16, 1.0F);
  const auto file = dir.path / "d.npy";
  io::write_npy(file, rows);
  MapRequest request;
  request.sessions = {SessionSource{{file}}};
  const std::size_t exact = peak(request, n, MapEngine::exact), fast = peak(request, n, MapEngine::fast),
                    streamed = peak(request, n, MapEngine::streaming), sparse = peak(request, n, MapEngine::sparse);
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
  EXPECT_EQ(streaming_obstacle(chi2, InputKind::descriptors)->subject(), "--metric");
  EXPECT_TRUE(streaming_obstacle(request, InputKind::similarity).has_value());
  EXPECT_FALSE(streaming_obstacle(request, InputKind::descriptors).has_value());

  // The one translation: an engine asked for is kept (and said only when the settings change), automatic is
  // chosen by the budget and said.
  MapRequest asked = request;
  asked.engine = MapEngine::exact;
  EXPECT_EQ(resolve_engine(asked, InputKind::descriptors, n, 4 * fast - m), "");
  EXPECT_EQ(asked.settings.map.engine, mapping::MapConfig::Engine::exact);
  MapRequest automatic = request;
  const auto note = resolve_engine(automatic, InputKind::descriptors, n, 4 * fast - m);
  EXPECT_EQ(automatic.engine, MapEngine::streaming);
  EXPECT_EQ(automatic.settings.map.engine, mapping::MapConfig::Engine::fast);
  EXPECT_EQ(note.rfind("engine streaming: ", 0), 0U) << note;
  MapRequest unknown = request;
  resolve_engine(unknown, InputKind::descriptors, std::nullopt, 4 * fast - m);
  EXPECT_EQ(unknown.engine, MapEngine::exact);
}

// check_request: each refusal names the option that earns it; a request that can stream passes.
TEST(EngineChoice, CheckRequestNamesTheOptionInTheWay) {
  const auto subject = [](const MapRequest& request, InputKind kind) -> std::string {
    try {
      check_request(request, kind);
    } catch (const InputError& e) {
      return e.subject();
    }
    return "";
  };
  MapRequest request;
  EXPECT_EQ(subject(request, InputKind::descriptors), "input");
  request.sessions = {SessionSource{{"d.npy"}}};
  EXPECT_EQ(subject(request, InputKind::descriptors), "");
  request.sparse.neighbours = 5;
  EXPECT_EQ(subject(request, InputKind::descriptors), "--neighbours");
  request.engine = MapEngine::sparse;
  EXPECT_EQ(subject(request, InputKind::descriptors), "");
  EXPECT_EQ(subject(request, InputKind::similarity), "--sparse");
  request.engine = MapEngine::streaming;
  request.sparse = {};
  EXPECT_EQ(subject(request, InputKind::similarity), "--streaming");
  MapRequest changed = request;
  changed.settings = apply_overrides(request.settings, {.described = {.kappa = 2.0F}});
  EXPECT_EQ(subject(changed, InputKind::descriptors), "--kappa");
  changed.settings = apply_overrides(request.settings, {.contrast_window = 0});
  EXPECT_EQ(subject(changed, InputKind::descriptors), "--contrast-window");
  changed.settings = apply_overrides(request.settings, {.described = {.descriptors = {{Descriptor::joint_histogram}}}});
  EXPECT_EQ(subject(changed, InputKind::images), "--descriptor");
  EXPECT_EQ(subject(changed, InputKind::descriptors), "");  // a descriptors.npy is its own vector descriptor
  changed = request;
  changed.preset = "paper";
  EXPECT_EQ(subject(changed, InputKind::descriptors), "--preset");
  changed = request;
  changed.truth.same_place = "truth.png";
  EXPECT_EQ(subject(changed, InputKind::descriptors), "--ground-truth");
  changed.engine = MapEngine::fast;
  EXPECT_EQ(subject(changed, InputKind::descriptors), "");
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
  const auto note = apply_engine(request, InputKind::images, MapEngine::streaming);
  EXPECT_EQ(request.engine, MapEngine::streaming);
  EXPECT_EQ(request.settings.map.engine, mapping::MapConfig::Engine::fast);
  EXPECT_EQ(note.rfind("images compared by the patch", 0), 0U) << note;
  EXPECT_EQ(apply_engine(request, InputKind::images, MapEngine::exact), "");
  EXPECT_EQ(request.settings.map.engine, mapping::MapConfig::Engine::exact);
}

}  // namespace
}  // namespace seqtopo::pipeline
