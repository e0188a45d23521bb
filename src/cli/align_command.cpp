// seqtopo align: the alignment engine on its own (INTERFACE.md).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <random>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/alignment_json.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/fasta.hpp"
#include "seqtopo/io/npy.hpp"

namespace seqtopo::cli::align_command {
namespace {

struct AlignOptions {
  std::string a_path, b_path, scores_path, json_path = "-", text_path;
  float match = 1.0F, mismatch = -1.0F;
  float gap = 1.0F;
  std::optional<float> gap_a, gap_b, cap;
  std::optional<float> threshold;  // default: auto (FASTA), 0 (--scores)
  bool threshold_auto = false, case_sensitive = false;
  std::size_t max_alignments = 100;
  bool reverse = false, self = false;
  std::size_t min_separation = 1;
};

// The default threshold of two letter sequences: the best score of A against B shuffled (the same letters in a
// random order, so no shared stretch survives), the highest of three shuffles (fixed seed). What scores above it
// is more than the sequences' composition gives by chance; with the default gap of 1, two random DNA sequences
// of 600 letters align with scores near 65 by chance alone, far above any exact-match count.
float chance_threshold(const std::string& a, const std::string& b, float match, float mismatch,
                       align::AlignConfig config, bool reverse) {
  config.max_alignments = 1;
  config.threshold = 0;
  config.self = false;
  std::mt19937 random(12345);
  float best = 0;
  for (int k = 0; k < 3; ++k) {
    std::string shuffled = b;
    std::shuffle(shuffled.begin(), shuffled.end(), random);
    const auto source = align::ScoreSource::function(a.size(), shuffled.size(), [&](std::size_t i, std::size_t j) {
      return a[i] == shuffled[j] ? match : mismatch;
    });
    const auto found = reverse ? align::local_alignments_both(source, config) : align::local_alignments(source, config);
    if (!found.empty()) best = std::max(best, found.front().score);
  }
  return best;
}

// Human-readable alignments, as in BLAST's pairwise view: A above, B below (in the order the alignment reads
// it: backwards for a reverse alignment), '|' for equal letters, '.' for different ones, '-' for a gap.
std::string alignments_text(const std::vector<align::LocalAlignment>& alignments, const std::string* a,
                            const std::string* b, bool case_sensitive) {
  std::string out;
  const auto same = [case_sensitive](char x, char y) {
    return case_sensitive ? x == y
                          : std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
  };
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    const auto& al = alignments[k];
    const bool reverse = al.direction == align::Direction::reverse;
    out += fmt::format("# {}  score {:g}  {}  A {}..{}  B {}..{}  ({} aligned pairs)\n", k + 1, al.score,
                       align::to_string(al.direction), al.a_begin, al.a_end - 1, al.b_begin, al.b_end - 1,
                       al.pairs.size());
    if (!a || !b || al.pairs.empty()) {
      std::string pairs;
      for (std::size_t p = 0; p < al.pairs.size() && p < 12; ++p)
        pairs += fmt::format(" ({},{})", al.pairs[p].first, al.pairs[p].second);
      out += "  pairs" + pairs + (al.pairs.size() > 12 ? " ..." : "") + "\n\n";
      continue;
    }
    std::string top, mid, bottom;
    for (std::size_t p = 0; p < al.pairs.size(); ++p) {
      const auto [i, j] = al.pairs[p];
      if (p > 0) {
        const auto [pi, pj] = al.pairs[p - 1];
        for (std::size_t x = pi + 1; x < i; ++x) top += (*a)[x], mid += ' ', bottom += '-';
        if (!reverse) {
          for (std::size_t y = pj + 1; y < j; ++y) top += '-', mid += ' ', bottom += (*b)[y];
        } else {
          for (std::size_t y = pj; y-- > j + 1;) top += '-', mid += ' ', bottom += (*b)[y];
        }
      }
      top += (*a)[i];
      bottom += (*b)[j];
      mid += same((*a)[i], (*b)[j]) ? '|' : '.';
    }
    // Rows of 60 columns with the positions of their first and last letters.
    std::size_t ai = al.pairs.front().first, bj = al.pairs.front().second;
    for (std::size_t at = 0; at < top.size(); at += 60) {
      const std::size_t len = std::min<std::size_t>(60, top.size() - at);
      const auto letters = [&](const std::string& row) {
        return static_cast<std::size_t>(std::count_if(row.begin() + static_cast<std::ptrdiff_t>(at),
                                                      row.begin() + static_cast<std::ptrdiff_t>(at + len),
                                                      [](char c) { return c != '-'; }));
      };
      const std::size_t na = letters(top), nb = letters(bottom);
      const std::size_t a_last = na ? ai + na - 1 : ai;
      const std::size_t b_last = nb ? (reverse ? bj - (nb - 1) : bj + nb - 1) : bj;
      out += fmt::format("A {:>7}  {}  {}\n", ai, top.substr(at, len), a_last);
      out += fmt::format("  {:>7}  {}\n", "", mid.substr(at, len));
      out += fmt::format("B {:>7}  {}  {}\n\n", bj, bottom.substr(at, len), b_last);
      ai += na;
      bj = reverse ? bj - nb : bj + nb;
    }
  }
  if (alignments.empty()) out += "no alignment scores above the threshold\n";
  return out;
}

void run(const AlignOptions& o) {
  if (o.scores_path.empty() == o.a_path.empty())
    throw InputError("--a/--scores", "give either --a (and --b) or --scores");
  if (!o.scores_path.empty() && !o.b_path.empty()) throw InputError("--b", "cannot be combined with --scores");

  align::AlignConfig config;
  config.gap_a = o.gap_a.value_or(o.gap);
  config.gap_b = o.gap_b.value_or(o.gap);
  config.cap = o.cap;
  config.threshold = o.threshold.value_or(0.0F);
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
  }
  std::string a, b;  // the letters (FASTA input), kept for the text view
  if (o.scores_path.empty()) {
    // Soft-masked FASTA (lower case = repeats) compares by letter: acgt matches ACGT unless --case-sensitive.
    const auto letters = [&](const std::string& path) {
      std::string s = io::read_fasta(path).front().sequence;
      if (!o.case_sensitive) {
        std::transform(s.begin(), s.end(), s.begin(),
                       [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
      }
      return s;
    };
    a = letters(o.a_path);
    const bool self = o.b_path.empty() || o.self;
    b = o.b_path.empty() ? a : letters(o.b_path);
    if (self && a != b) throw InputError("--self", "A and B differ; --self needs the same sequence");
    config.self = self;
    if (!o.threshold) config.threshold = chance_threshold(a, b, o.match, o.mismatch, config, o.reverse);
    const float match = o.match, mismatch = o.mismatch;
    run_engine(align::ScoreSource::function(
        a.size(), b.size(),
        [&a, &b, match, mismatch](std::size_t i, std::size_t j) { return a[i] == b[j] ? match : mismatch; }));
  }

  const bool text_on_stdout = o.text_path == "-";
  if (!o.text_path.empty()) {
    // The letters shown are the file's own (soft-masking kept) when the comparison ignored case.
    std::string shown_a = a, shown_b = b;
    if (o.scores_path.empty() && !o.case_sensitive) {
      shown_a = io::read_fasta(o.a_path).front().sequence;
      shown_b = o.b_path.empty() ? shown_a : io::read_fasta(o.b_path).front().sequence;
    }
    const std::string view = alignments_text(alignments, o.scores_path.empty() ? &shown_a : nullptr,
                                             o.scores_path.empty() ? &shown_b : nullptr, o.case_sensitive);
    if (text_on_stdout) {
      std::cout << view;
    } else {
      io::write_file_atomic(o.text_path, view);
    }
  }
  const std::string json = formats::alignments_to_json(alignments).dump(1) + "\n";
  if (o.json_path != "-") {
    io::write_file_atomic(o.json_path, json);
  } else if (!text_on_stdout) {
    std::cout << json;
  }
  std::cerr << fmt::format("seqtopo align: {} alignment(s){} (threshold {:g}{})\n", alignments.size(),
                           alignments.empty() ? "" : fmt::format(", best score {}", alignments.front().score),
                           config.threshold, o.threshold || !o.scores_path.empty() ? "" : ", auto: above chance");
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
       add_number_or(app, "--threshold", o->threshold, "auto", o->threshold_auto, kNonNegative,
                     "minimum alignment score reported (always > 0); default auto for FASTA: above chance, the best "
                     "score of A against B shuffled (highest of 3 shuffles); 0 for --scores");
       app.add_flag("--case-sensitive", o->case_sensitive,
                    "FASTA: lower-case (soft-masked) letters differ from upper-case ones (default: acgt = ACGT)");
       app.add_option("--text", o->text_path,
                      "also write the alignments for reading, letters over letters ('-' = standard output, "
                      "instead of the JSON unless --json names a file)");
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
}  // namespace seqtopo::cli::align_command
