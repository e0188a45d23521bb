// The engine against EMBOSS matcher (Huang & Miller's SIM: Waterman-Eggert non-intersecting local
// alignments) on random DNA pairs with planted repeats.
//
// Gap convention: matcher charges a gap of length L as gapopen + gapextend * (L - 1) (checked by hand
// on a planted gap: open 3 / extend 2 costs 3, 5, 7, 9 for L = 1..4). Our linear gap L * G is
// therefore -gapopen G -gapextend G (SIM's affine parts then vanish: its extra open cost is 0).
//
// Tie conventions of SIM as matcher implements them (they decide which pairs an alignment consumes,
// hence every later score), and what the engine does (smith_waterman.hpp):
//  * Every cell carries its best score and the start point of an alignment reaching it; among equal
//    scores (diagonal, vertical, horizontal, or a fresh start at 0) the larger start point wins, row
//    first, then column: the latest start. The engine: the same start rule.
//  * Candidates are kept one per start point (the K best); a candidate's end is the first cell in
//    row-major order reaching its score (only a strictly larger score moves it). The best candidate is
//    taken, the earliest in the list among equals. The engine: the first maximal cell in row-major
//    order (with a cap it keeps taking a plateau at the cap whole; matcher has no cap).
//  * The path between start and end is recovered by a linear-space divide and conquer: at the middle
//    row the leftmost optimal column, or the rightmost optimal one that is entered without a vertical
//    step and left with one; a single row prefers all gaps over an equally good pair, else its
//    leftmost best pair. Used pairs are forbidden to diagonal steps throughout. The engine: the same
//    bisection, run on the tight steps of its own table.
// With these, the top-10 lists agree score for score in all 300 cases here, and nearly every alignment
// uses the same pairs. What must agree: the best score, in every case, and the top-10 lists in the
// large majority. Where a later score differs, an earlier alignment with the same score must have
// consumed a different set of pairs (two equally good choices): the lists are identical up to the
// first alignment whose pairs differ, and the test checks exactly that instead of loosening the
// comparison.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "common/run_command.hpp"
#include "common/sanitizers.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

constexpr int kMatch = 5, kMismatch = -4;

struct MatcherAlignment {
  int score = 0;
  std::set<std::pair<std::size_t, std::size_t>> pairs;  // 0-based (i, j)
};

// Parses matcher's "pair" format: per alignment a "# Score:" line, then blocks of
// "a <start> <gapped text> <end>" / "b <start> <gapped text> <end>" lines.
std::vector<MatcherAlignment> parse_pairs(const std::string& text) {
  std::vector<MatcherAlignment> out;
  std::istringstream in(text);
  std::string line, a_text, b_text;
  std::size_t a_start = 0, b_start = 0;
  bool have_a = false, have_b = false;
  const std::regex seq_line(R"(^(\S+)\s+(\d+)\s+(\S+)\s+\d+\s*$)");
  auto flush = [&] {
    if (out.empty() || a_text.empty()) return;
    std::size_t i = a_start, j = b_start;
    for (std::size_t k = 0; k < a_text.size() && k < b_text.size(); ++k) {
      const bool ga = a_text[k] == '-', gb = b_text[k] == '-';
      if (!ga && !gb) out.back().pairs.insert({i, j});
      if (!ga) ++i;
      if (!gb) ++j;
    }
    a_text.clear();
    b_text.clear();
    have_a = have_b = false;
  };
  while (std::getline(in, line)) {
    if (line.rfind("# Score:", 0) == 0) {
      flush();
      out.push_back({std::stoi(line.substr(8)), {}});
      continue;
    }
    std::smatch m;
    if (line.empty() || line[0] == '#' || !std::regex_match(line, m, seq_line)) continue;
    if (m[1] == "a") {
      if (!have_a) a_start = std::stoul(m[2]) - 1;
      have_a = true;
      a_text += m[3];
    } else if (m[1] == "b") {
      if (!have_b) b_start = std::stoul(m[2]) - 1;
      have_b = true;
      b_text += m[3];
    }
  }
  flush();
  return out;
}

std::string random_dna(std::mt19937& rng, std::size_t n) {
  static const char kBases[] = "ACGT";
  std::uniform_int_distribution<int> base(0, 3);
  std::string s;
  for (std::size_t k = 0; k < n; ++k) s.push_back(kBases[base(rng)]);
  return s;
}

// Copies `repeat` into s at `at`, with point mutations and small indels.
void plant(std::mt19937& rng, std::string& s, const std::string& repeat, std::size_t at) {
  std::string mutated;
  std::uniform_real_distribution<double> u(0, 1);
  for (char c : repeat) {
    const double r = u(rng);
    if (r < 0.06) continue;                                                     // deletion
    if (r < 0.12) mutated.push_back("ACGT"[static_cast<int>(u(rng) * 4) % 4]);  // insertion before c
    mutated.push_back(r < 0.2 ? "ACGT"[static_cast<int>(u(rng) * 4) % 4] : c);  // substitution
  }
  s.replace(at, std::min(mutated.size(), s.size() - at), mutated.substr(0, s.size() - at));
}

class AgainstMatcher : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(test_support::run_command("command -v matcher").status, 0)
        << "EMBOSS matcher is required (scripts/setup.sh)";
    std::ofstream m(dir_.path / "DNAMATRIX");
    m << "   A  C  G  T\n";
    for (char r : std::string("ACGT")) {
      m << r;
      for (char c : std::string("ACGT")) m << ' ' << (r == c ? kMatch : kMismatch);
      m << "\n";
    }
  }

  std::vector<MatcherAlignment> matcher(const std::string& a, const std::string& b, int gap, int count) {
    dir_.write("a.fa", ">a\n" + a + "\n");
    dir_.write("b.fa", ">b\n" + b + "\n");
    // matcher's stdout is the alignments; its stderr (a banner) is not looked at.
    const std::string cmd = "cd " + dir_.path.string() +
                            " && matcher -asequence a.fa -bsequence b.fa -datafile ./DNAMATRIX -gapopen " +
                            std::to_string(gap) + " -gapextend " + std::to_string(gap) + " -alternatives " +
                            std::to_string(count) + " -aformat3 pair -outfile stdout";
    return parse_pairs(test_support::run_command(cmd).out);
  }

  const test_support::TempDir dir_;
};

std::set<std::pair<std::size_t, std::size_t>> pair_set(const align::LocalAlignment& a) {
  return {a.pairs.begin(), a.pairs.end()};
}

// One line per list: score and the A range (first..last aligned element) of each alignment.
std::string describe(const std::vector<align::LocalAlignment>& got, const std::vector<MatcherAlignment>& want) {
  std::ostringstream out;
  out << " ours:";
  for (const auto& x : got) out << ' ' << x.score << '[' << x.a_begin << ".." << x.a_end - 1 << ']';
  out << "\n them:";
  for (const auto& x : want) {
    out << ' ' << x.score << '[' << (x.pairs.empty() ? 0 : x.pairs.begin()->first) << ".."
        << (x.pairs.empty() ? 0 : x.pairs.rbegin()->first) << ']';
  }
  return out.str();
}

TEST_F(AgainstMatcher, BestScoreAlwaysAndTopTenExplained) {
  SEQTOPO_SKIP_UNDER_SANITIZERS("many random problems");
  std::mt19937 rng(424242);
  const int cases = 300;
  int top10_identical = 0, explained = 0, compared_scores = 0, same_pairs = 0;
  for (int c = 0; c < cases; ++c) {
    const std::size_t n = std::uniform_int_distribution<std::size_t>(40, 160)(rng);
    const std::size_t m = std::uniform_int_distribution<std::size_t>(40, 160)(rng);
    std::string a = random_dna(rng, n), b = random_dna(rng, m);
    // one to three planted repeats
    const int repeats = std::uniform_int_distribution<int>(1, 3)(rng);
    for (int r = 0; r < repeats; ++r) {
      const std::size_t len = std::uniform_int_distribution<std::size_t>(10, 30)(rng);
      const std::size_t from = std::uniform_int_distribution<std::size_t>(0, n - len)(rng);
      const std::size_t to = std::uniform_int_distribution<std::size_t>(0, m - 1)(rng);
      plant(rng, b, a.substr(from, len), to);
    }
    const int gap = std::uniform_int_distribution<int>(2, 8)(rng);

    const auto want = matcher(a, b, gap, 10);
    ASSERT_FALSE(want.empty()) << "matcher produced no alignment; case " << c;
    align::AlignConfig config;
    config.gap_a = config.gap_b = static_cast<float>(gap);
    config.max_alignments = want.size();
    const auto got = align::local_alignments(
        align::ScoreSource::function(
            n, m, [&](std::size_t i, std::size_t j) { return static_cast<float>(a[i] == b[j] ? kMatch : kMismatch); }),
        config);
    ASSERT_FALSE(got.empty());
    ASSERT_EQ(got.front().score, static_cast<float>(want.front().score)) << "best score differs; case " << c;

    // alignments of matcher's list that the engine also found, pair for pair
    for (const auto& w : want) {
      same_pairs += std::any_of(got.begin(), got.end(), [&](const auto& x) { return pair_set(x) == w.pairs; });
    }
    std::size_t k = 0;
    while (k < want.size() && k < got.size() && got[k].score == static_cast<float>(want[k].score)) ++k;
    compared_scores += static_cast<int>(std::min(want.size(), got.size()));
    if (k == std::min(want.size(), got.size())) {
      ++top10_identical;
      continue;
    }
    // Scores first differ at k: some earlier alignment must have taken another, equally good path.
    bool different_earlier = false;
    for (std::size_t q = 0; q < k; ++q) different_earlier |= pair_set(got[q]) != want[q].pairs;
    EXPECT_TRUE(different_earlier) << "case " << c << ": score " << k << " differs (" << got[k].score << " vs "
                                   << want[k].score << ") although every earlier alignment used the same pairs\n"
                                   << describe(got, want);
    ++explained;
    if (std::getenv("SEQTOPO_DEBUG_MATCHER")) {
      std::printf("case %d differs at %zu\n%s\n", c, k, describe(got, want).c_str());
    }
  }
  // Observed: 300 of 300. The margin is for ties among equal candidates, where matcher's order
  // (its candidate list) and ours (row-major) may pick differently.
  EXPECT_GE(top10_identical, cases * 97 / 100) << explained << " cases differed after an earlier tie";
  RecordProperty("cases", cases);
  RecordProperty("top10_identical", top10_identical);
  RecordProperty("scores_compared", compared_scores);
  RecordProperty("alignments_with_same_pairs", same_pairs);
  std::printf(
      "matcher comparison: %d cases, %d scores compared, top-10 identical in %d, explained ties in %d, "
      "%d alignments with the same pairs\n",
      cases, compared_scores, top10_identical, explained, same_pairs);
}

}  // namespace
}  // namespace seqtopo
