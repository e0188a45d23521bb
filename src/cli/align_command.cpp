// seqtopo align: the alignment engine on its own (INTERFACE.md).
#include <fmt/format.h>

#include <iostream>
#include <limits>

#include "command_registry.hpp"
#include "number_options.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/alignment_json.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/fasta.hpp"
#include "seqtopo/io/npy.hpp"

namespace seqtopo::cli {
namespace {

struct AlignOptions {
  std::string a_path, b_path, scores_path, json_path = "-";
  float match = 1.0F, mismatch = -1.0F;
  float gap = 1.0F;
  std::optional<float> gap_a, gap_b, cap;
  float threshold = 0.0F;
  std::size_t max_alignments = 100;
  bool reverse = false, self = false;
  std::size_t min_separation = 1;
};

void run(const AlignOptions& o) {
  if (o.scores_path.empty() == o.a_path.empty())
    throw InputError("--a/--scores", "give either --a (and --b) or --scores");
  if (!o.scores_path.empty() && !o.b_path.empty()) throw InputError("--b", "cannot be combined with --scores");

  align::AlignConfig config;
  config.gap_a = o.gap_a.value_or(o.gap);
  config.gap_b = o.gap_b.value_or(o.gap);
  config.cap = o.cap;
  config.threshold = o.threshold;
  config.max_alignments = o.max_alignments == 0 ? std::numeric_limits<std::size_t>::max() : o.max_alignments;
  config.min_separation = o.min_separation;

  std::vector<align::LocalAlignment> alignments;
  auto run_engine = [&](const align::ScoreSource& source) {
    alignments = o.reverse ? align::local_alignments_both(source, config) : align::local_alignments(source, config);
  };
  if (!o.scores_path.empty()) {
    const auto scores = io::read_npy_matrix<float>(o.scores_path);
    if (o.self && !scores.square()) {
      throw InputError(o.scores_path,
                       fmt::format("--self needs a square matrix, got {} x {}", scores.rows, scores.cols));
    }
    config.self = o.self;
    run_engine(align::ScoreSource::dense(scores.values, scores.rows, scores.cols));
  } else {
    const std::string a = io::read_fasta(o.a_path).front().sequence;
    const bool self = o.b_path.empty() || o.self;
    const std::string b = o.b_path.empty() ? a : io::read_fasta(o.b_path).front().sequence;
    if (self && a != b) throw InputError("--self", "A and B differ; --self needs the same sequence");
    config.self = self;
    const float match = o.match, mismatch = o.mismatch;
    run_engine(align::ScoreSource::function(
        a.size(), b.size(),
        [&a, &b, match, mismatch](std::size_t i, std::size_t j) { return a[i] == b[j] ? match : mismatch; }));
  }

  const std::string text = formats::alignments_to_json(alignments).dump(1) + "\n";
  if (o.json_path == "-") {
    std::cout << text;
  } else {
    io::write_file_atomic(o.json_path, text);
  }
  std::cerr << fmt::format("seqtopo align: {} alignment(s){}\n", alignments.size(),
                           alignments.empty() ? "" : fmt::format(", best score {}", alignments.front().score));
}

const RegisterCommand registered{
    {"align", "All non-intersecting local alignments of two sequences (FASTA) or of a score matrix (.npy), best first",
     [](CLI::App& app) {
       auto o = std::make_shared<AlignOptions>();
       app.add_option("--a", o->a_path, "FASTA file with sequence A (first record); alone, A is aligned with itself")
           ->check(CLI::ExistingFile);
       app.add_option("--b", o->b_path, "FASTA file with sequence B (first record)")->check(CLI::ExistingFile);
       app.add_option("--scores", o->scores_path, "score matrix S.npy (float32/float64, rows = A, columns = B)")
           ->check(CLI::ExistingFile);
       add_number(app, "--match", o->match, kAnyFinite, "score of two equal symbols (FASTA input)");
       add_number(app, "--mismatch", o->mismatch, kAnyFinite, "score of two different symbols (FASTA input)");
       add_number(app, "--gap", o->gap, kNonNegative, "linear gap penalty: a gap of length L costs L*G");
       add_number(app, "--gap-a", o->gap_a, kNonNegative, "gap penalty for skipping an element of A (default: --gap)");
       add_number(app, "--gap-b", o->gap_b, kNonNegative, "gap penalty for skipping an element of B (default: --gap)");
       add_number(app, "--cap", o->cap, kPositive,
                  "upper bound on the cumulative score (default: none, classical Smith-Waterman)");
       add_number(app, "--threshold", o->threshold, kNonNegative, "minimum alignment score reported (always > 0)");
       add_number(app, "--max-alignments", o->max_alignments, kNonNegative,
                  "at most this many alignments, best first (0 = all)");
       app.add_flag("--reverse", o->reverse, "also search reverse alignments (A against B read backwards)");
       app.add_flag("--self", o->self, "A and B are the same sequence: search one triangle, skip the diagonal band");
       add_number(app, "--min-separation", o->min_separation, kAtLeastOne,
                  "self alignment: pairs (i, j) count only if i - j >= F");
       app.add_option("--json", o->json_path, "output alignments.json ('-' = standard output)")->capture_default_str();
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli
