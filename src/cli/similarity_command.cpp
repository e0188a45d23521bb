// seqtopo similarity: a sequence in, the similarity matrix S = 1 - kappa * D out (mapping paper IV-A).
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <memory>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "progress.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"
#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#include "sequence_options.hpp"

namespace seqtopo::cli::similarity_command {
namespace {

struct SimilarityOptions {
  std::string input, against, out_dir = "seqtopo-out", input_kind = "auto", descriptor = "joint-histogram";
  std::string metric;
  std::optional<float> kappa;
  bool kappa_auto = false;
  std::size_t every = 1;
  unsigned threads = 0;
  bool descriptor_given = false;
  SequenceOptions sequence;
};

void run(const SimilarityOptions& o) {
  pipeline::SimilarityConfig config;
  const auto kind = option_value("--input-kind", [&] { return pipeline::parse_input_kind(o.input_kind); });
  config.descriptor = option_value("--descriptor", [&] { return pipeline::parse_descriptor(o.descriptor); });
  if (!o.metric.empty())
    config.distance = option_value("--metric", [&] { return similarity::parse_distance(o.metric); });
  config.kappa = o.kappa;
  config.threads = resolve_threads(o.threads);
  Progress progress("seqtopo similarity");
  progress.plan({"similarity", "files"});
  config.note = [&progress](std::string_view text) { progress.line(text); };
  config.progress = [&progress](std::string_view stage, std::size_t done, std::size_t total) {
    progress.advance(done, total, stage == "matrix" ? "cells of the matrix" : "images described");
  };

  io::OutputDirectory out(o.out_dir, {.inputs = {o.input, o.against}, .command = "seqtopo similarity"});
  pipeline::SequenceInput a{o.input, kind, o.every};
  pipeline::SequenceInput b{o.against, kind, o.every};
  o.sequence.apply(a);
  o.sequence.apply(b);
  pipeline::SimilarityResult result;
  progress.begin("similarity");
  try {
    result = o.against.empty() ? pipeline::compute_similarity(a, config) : pipeline::compute_similarity(a, b, config);
  } catch (const std::invalid_argument& e) {
    throw InputError(o.input, e.what());
  }
  progress.end();

  progress.begin("files");
  out.write("similarity.npy", io::encode_npy(result.similarity));
  plot::MatrixFigureConfig figure;
  figure.title = fmt::format("Similarity S = 1 - kappa D ({} x {})", result.similarity.rows, result.similarity.cols);
  figure.value_label = "similarity S";
  if (!o.against.empty()) figure.row_label = "INPUT frame", figure.column_label = "--against frame";
  out.write("similarity.png", plot::encode_png(plot::matrix_figure(result.similarity, {}, figure)));
  out.commit();
  progress.end();

  std::string kappa_text = "input was a similarity matrix";
  if (!std::isnan(result.kappa)) {
    kappa_text = result.kappa_auto
                     ? fmt::format("kappa {:.4g} (auto: S > 0 for the closest {:.2f}% of candidate pairs)",
                                   result.kappa, 100.0 * result.kappa_fraction)
                     : fmt::format("kappa {:.4g}", result.kappa);
  }
  progress.line(fmt::format(
      "{} x {}{}, {}; descriptors {:.2f} s, matrix {:.2f} s -> {}", result.similarity.rows, result.similarity.cols,
      result.distance ? fmt::format(" ({})", similarity::distance_name(*result.distance)) : "", kappa_text,
      result.seconds_descriptors, result.seconds_matrix, (out.dir() / "similarity.npy").string()));
}

const RegisterCommand registered{
    {"similarity", "Similarity matrix S = 1 - kappa * D of an image folder, video, descriptors.npy or similarity.npy",
     [](CLI::App& app) {
       auto o = std::make_shared<SimilarityOptions>();
       app.add_option("INPUT", o->input,
                      "image folder, video file, bag (.bag, .db3, .mcap), descriptors.npy (N x D) or similarity.npy")
           ->required()
           ->check(CLI::ExistingPath);
       app.add_option("--against", o->against, "second sequence of the same kind: N x M matrix, rows = INPUT")
           ->check(CLI::ExistingPath);
       app.add_option("--out", o->out_dir, "output folder for similarity.npy and similarity.png")
           ->capture_default_str();
       app.add_option("--input-kind", o->input_kind, "auto|images|video|descriptors|similarity")->capture_default_str();
       add_number(app, "--every", o->every, kAtLeastOne, "video: keep every K-th frame");
       app.add_option("--descriptor", o->descriptor,
                      "joint-histogram|patch|panorama|npy (a descriptors.npy input uses its rows)")
           ->capture_default_str();
       app.add_option(
           "--metric", o->metric,
           "chi2|l1|cosine|sad (default: chi2 for joint-histogram, sad for patch and panorama, cosine for npy)");
       add_number_or(app, "--kappa", o->kappa, "auto", o->kappa_auto, kPositive,
                     "K > 0 in S = 1 - K * D, or auto (the default; see docs/similarity.md)");
       add_number(app, "--threads", o->threads, kThreads, "worker threads (0 = all cores)");
       add_sequence_options(app, o->sequence);
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::similarity_command
