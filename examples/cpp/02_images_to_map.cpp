// 02: an image folder in, the whole `seqtopo map` job out: similarity, alignments, places, topology,
// accuracy against the ground truth, and the files (map.json, figures, report.html) in a folder.
//
//   ./02_images_to_map IMAGE_FOLDER [GROUND_TRUTH.bmp] [OUT_FOLDER]
//   corridor=/opt/seqtopo/share/seqtopo/rtabmap-corridor
//   ./02_images_to_map $corridor $corridor/ground_truth.bmp corridor-map
#include <cstdio>
#include <exception>
#include <string>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/outputs/map_outputs.hpp"
#include "seqtopo/pipeline/map_pipeline.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s IMAGE_FOLDER [GROUND_TRUTH] [OUT_FOLDER]\n", argv[0]);
    return 2;
  }
  namespace pipeline = seqtopo::pipeline;
  pipeline::MapRequest request;
  request.sessions = {pipeline::SessionSource{{argv[1]}}};
  request.settings = pipeline::map_preset("default");
  if (argc > 2) request.truth.same_place = argv[2];
  try {
    const pipeline::MapRun run =
        pipeline::map_sequence(request, {.progress = [](std::string_view line) {
                                 std::fprintf(stderr, "%.*s\n", static_cast<int>(line.size()), line.data());
                               }});
    std::printf("%zu images, %zu places, %zu junctions, %zu loop-closure pairs\n", run.result.map.labels.size(),
                run.result.map.places.size(), run.result.map.junctions.size(), run.result.pruning.pairs.size());
    if (run.metrics) {
      std::printf("loop closures: precision %.3f recall %.3f F1 %.3f\n", run.metrics->precision, run.metrics->recall,
                  run.metrics->f1);
    }
    if (argc > 3) {
      seqtopo::io::OutputDirectory out(argv[3]);
      seqtopo::outputs::write_map_outputs(run, out);
      seqtopo::outputs::write_map_report(run, out);
      std::printf("wrote %zu files to %s\n", out.commit().size(), argv[3]);
    }
  } catch (const seqtopo::InputError& e) {
    std::fprintf(stderr, "error: %s: %s\n", e.subject().c_str(), e.what());
    return 1;
  }
  return 0;
}
