// The fast engine against the scalar engine (itself tested against the naive reference) on the same
// quantized input: every alignment's score, direction, ranges and pairs must be identical, for every
// instruction set this CPU has and any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "random_problems.hpp"
#include "seqtopo/align/fast_alignment.hpp"
#include "seqtopo/align/smith_waterman.hpp"

namespace seqtopo {
namespace {

using align::AlignConfig;
using align::Direction;
using align::FastOptions;
using align::Isa;
using align::LocalAlignment;
using align::ScoreSource;

std::vector<Isa> isas() {
  std::vector<Isa> out{Isa::scalar};
  if (align::best_isa() == Isa::sse41 || align::best_isa() == Isa::avx2) out.push_back(Isa::sse41);
  if (align::best_isa() == Isa::avx2) out.push_back(Isa::avx2);
  return out;
}

// The scalar engine on the quantized input, scores back in score units.
std::vector<LocalAlignment> scalar_on_quantized(const ScoreSource& source, const AlignConfig& config, float scale,
                                                bool both = false) {
  const auto q_source = align::quantized(source, scale);
  const auto q_config = align::quantized(config, scale);
  auto out = both ? align::local_alignments_both(q_source, q_config, 1) : align::local_alignments(q_source, q_config);
  for (auto& a : out) a.score /= scale;
  return out;
}

void expect_same(const std::vector<LocalAlignment>& got, const std::vector<LocalAlignment>& want,
                 const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].score, want[k].score) << what << " alignment " << k;
    EXPECT_EQ(got[k].direction, want[k].direction) << what << " alignment " << k;
    EXPECT_EQ(got[k].a_begin, want[k].a_begin) << what << " alignment " << k;
    EXPECT_EQ(got[k].a_end, want[k].a_end) << what << " alignment " << k;
    EXPECT_EQ(got[k].b_begin, want[k].b_begin) << what << " alignment " << k;
    EXPECT_EQ(got[k].b_end, want[k].b_end) << what << " alignment " << k;
    EXPECT_EQ(got[k].pairs, want[k].pairs) << what << " alignment " << k;
  }
}

std::string describe(int case_id, const AlignConfig& c, float scale, Isa isa, unsigned threads) {
  return "case " + std::to_string(case_id) + " (" + (c.self ? "self " : "") + std::string(to_string(c.direction)) +
         ", scale " + std::to_string(scale) + ", " + std::string(to_string(isa)) + ", threads " +
         std::to_string(threads) + ")";
}

TEST(FastAlignment, RandomSmallProblemsEveryIsa) {
  std::mt19937 rng(20261123);
  const float scales[] = {0.0F, 1.0F, 2.0F, 8.0F, 64.0F};
  std::size_t compared = 0;
  for (int case_id = 0; case_id < 700; ++case_id) {
    const auto p = test_support::random_problem(rng, 40);
    const float scale = align::fast_scale(p.naive.config, {scales[case_id % 5], 1, Isa::best});
    const auto want = scalar_on_quantized(p.source(), p.naive.config, scale);
    compared += want.size();
    for (Isa isa : isas()) {
      expect_same(align::fast_local_alignments(p.source(), p.naive.config, {scale, 1, isa}), want,
                  describe(case_id, p.naive.config, scale, isa, 1));
    }
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(compared, 7000U);  // the generator must produce real work
}

TEST(FastAlignment, LargerProblemsThreadsAndMaxAlignments) {
  // Sizes across several vector widths, checkpoint intervals (64 rows) and column strips (512 columns).
  std::mt19937 rng(77);
  for (int case_id = 0; case_id < 36; ++case_id) {
    const bool large = case_id % 3 == 0;
    auto p = test_support::random_problem(rng, large ? 1100 : 200);
    auto& c = p.naive.config;
    c.max_alignments =
        case_id % 4 == 1 && !large ? std::numeric_limits<std::size_t>::max() : 1 + case_id % (large ? 6 : 25);
    if (c.self) c.min_separation = 1 + static_cast<std::size_t>(case_id % 7) * 3;
    if (large || (!c.cap && case_id % 2 == 0)) c.cap = 12.0F;
    const float scale = c.cap ? 0.0F : 4.0F;
    const float used = align::fast_scale(c, {scale, 1, Isa::best});
    const auto want = scalar_on_quantized(p.source(), c, used);
    for (unsigned threads : {1U, 2U, 3U}) {
      const Isa isa = isas()[static_cast<std::size_t>(case_id + threads) % isas().size()];
      expect_same(align::fast_local_alignments(p.source(), c, {scale, threads, isa}), want,
                  describe(case_id, c, used, isa, threads));
    }
    if (::testing::Test::HasFailure()) return;
  }
}

// A mapping-like similarity matrix: negative noise with planted revisits (diagonal and anti-diagonal
// stretches) that a cap turns into long plateaus.
std::vector<float> revisit_matrix(std::mt19937& rng, std::size_t n, bool symmetric) {
  std::normal_distribution<float> noise(-0.6F, 0.5F);
  std::vector<float> s(n * n);
  for (auto& v : s) v = noise(rng);
  std::uniform_int_distribution<std::size_t> pos(0, n - 1);
  for (int r = 0; r < 6; ++r) {
    const std::size_t len = n / 6, i0 = pos(rng), j0 = pos(rng);
    const bool anti = r % 2 == 1;
    for (std::size_t k = 0; k < len; ++k) {
      const std::size_t i = i0 + k, j = anti ? j0 + len - k : j0 + k;
      if (i < n && j < n) s[i * n + j] = 1.0F;
    }
  }
  if (symmetric) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < i; ++j) s[j * n + i] = s[i * n + j];
    }
  }
  return s;
}

TEST(FastAlignment, PlantedRevisitsWithCapBothDirections) {
  std::mt19937 rng(5);
  for (int case_id = 0; case_id < 12; ++case_id) {
    const std::size_t n = 150 + static_cast<std::size_t>(case_id) * 71;
    const bool self = case_id % 2 == 1;
    const auto s = revisit_matrix(rng, n, self);
    const auto source = ScoreSource::dense(s, n, n);
    AlignConfig c;
    c.gap_a = c.gap_b = 1.5F;
    c.cap = case_id % 3 == 2 ? 40.0F : 8.0F;
    c.threshold = 4.0F;
    c.self = self;
    c.min_separation = 5;
    const float scale = align::fast_scale(c);
    const auto want = scalar_on_quantized(source, c, scale, true);
    ASSERT_FALSE(want.empty());
    for (unsigned threads : {1U, 2U, 3U}) {
      const Isa isa = isas()[static_cast<std::size_t>(case_id) % isas().size()];
      expect_same(align::fast_local_alignments_both(source, c, {0.0F, threads, isa}), want,
                  describe(case_id, c, scale, isa, threads));
    }
  }
}

TEST(FastAlignment, ColumnStripsOnManyThreadsGiveIdenticalResults) {
  // Wide enough for up to four strips of >= 512 columns, in both directions, with and without the
  // self triangle (whose region edge crosses the strip boundaries).
  std::mt19937 rng(21);
  const std::size_t n = 2100;
  for (int case_id = 0; case_id < 4; ++case_id) {
    const bool self = case_id >= 2;
    const auto s = revisit_matrix(rng, n, self);
    const auto source = ScoreSource::dense(s, n, n);
    AlignConfig c;
    c.gap_a = 1.0F;
    c.gap_b = 2.0F;
    c.cap = 10.0F;
    c.threshold = 3.0F;
    c.max_alignments = 8;
    c.self = self;
    c.min_separation = 9;
    c.direction = case_id % 2 == 0 ? Direction::forward : Direction::reverse;
    const float scale = align::fast_scale(c);
    const auto want = scalar_on_quantized(source, c, scale);
    ASSERT_FALSE(want.empty());
    for (unsigned threads : {1U, 2U, 3U, 4U}) {
      expect_same(align::fast_local_alignments(source, c, {0.0F, threads, Isa::best}), want,
                  describe(case_id, c, scale, Isa::best, threads));
      EXPECT_EQ(align::fast_best_score(source, c, {0.0F, threads, Isa::best}), *c.cap) << "case " << case_id;
    }
  }
}

TEST(FastAlignment, LongPlateausAndFarReachingUpdatesAcrossTiles) {
  // The engine keeps H only at tile boundaries (every 32nd row and column) and recomputes pieces of
  // it: plateaus far wider than its first plateau window (256 columns), overlapping revisits whose
  // removal changes tiles far below and right of them, sizes that are not multiples of the tile.
  std::mt19937 rng(33);
  std::normal_distribution<float> noise(-0.8F, 0.4F);
  for (int case_id = 0; case_id < 4; ++case_id) {
    const std::size_t m = 1201 + static_cast<std::size_t>(case_id) * 37, n = case_id < 2 ? 1337 : m;
    const bool self = case_id >= 2;
    std::vector<float> s(m * n);
    for (auto& v : s) v = noise(rng);
    // one 700-long revisit, one crossing it, one parallel to it (anti-diagonal ones for the reverse pass)
    const Direction direction = case_id % 2 == 0 ? Direction::forward : Direction::reverse;
    auto plant = [&](std::size_t i0, std::size_t j0, std::size_t len, bool crossing) {
      const bool anti = crossing != (direction == Direction::reverse);
      for (std::size_t k = 0; k < len; ++k) {
        const std::size_t i = i0 + k, j = anti ? j0 + len - 1 - k : j0 + k;
        if (i < m && j < n) s[i * n + j] = self && i < j ? s[i * n + j] : 1.0F;
      }
    };
    plant(400, 20, 700, false);
    plant(500, 100, 400, true);
    plant(430, 23, 300, false);
    if (self) {
      for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = 0; j < i; ++j) s[j * n + i] = s[i * n + j];
      }
    }
    const auto source = ScoreSource::dense(s, m, n);
    AlignConfig c;
    c.gap_a = 1.0F;
    c.gap_b = 1.5F;
    c.cap = 6.0F;
    c.threshold = 2.0F;
    c.self = self;
    c.min_separation = 10;
    c.direction = direction;
    const float scale = align::fast_scale(c);
    const auto want = scalar_on_quantized(source, c, scale, self);
    ASSERT_GE(want.size(), 2U) << "case " << case_id;
    std::size_t longest = 0;
    for (const auto& a : want) longest = std::max(longest, a.pairs.size());
    ASSERT_GT(longest, 500U) << "case " << case_id;  // a plateau twice the first window
    for (unsigned threads : {1U, 2U}) {
      const FastOptions options{0.0F, threads, Isa::best};
      expect_same(self ? align::fast_local_alignments_both(source, c, options)
                       : align::fast_local_alignments(source, c, options),
                  want, describe(case_id, c, scale, Isa::best, threads));
    }
  }
}

// Random sequences of na and nb letters of k, and a substitution matrix: 5 on the diagonal, a whole number in
// [lowest_mismatch, -1] elsewhere.
struct RandomLetters {
  std::vector<std::uint8_t> a, b;
  std::vector<float> matrix;
};
RandomLetters random_letters(std::mt19937& rng, std::size_t k, std::size_t na, std::size_t nb, int lowest_mismatch) {
  RandomLetters p{std::vector<std::uint8_t>(na), std::vector<std::uint8_t>(nb), std::vector<float>(k * k)};
  std::uniform_int_distribution<int> letter(0, static_cast<int>(k) - 1);
  for (auto& x : p.a) x = static_cast<std::uint8_t>(letter(rng));
  for (auto& x : p.b) x = static_cast<std::uint8_t>(letter(rng));
  std::uniform_int_distribution<int> mismatch(lowest_mismatch, -1);
  for (std::size_t x = 0; x < k; ++x) {
    for (std::size_t y = 0; y < k; ++y) p.matrix[x * k + y] = x == y ? 5.0F : static_cast<float>(mismatch(rng));
  }
  return p;
}

TEST(FastAlignment, LetterScoresEqualTheirScoreSource) {
  std::mt19937 rng(9);
  for (int case_id = 0; case_id < 24; ++case_id) {
    const std::size_t k = 4 + static_cast<std::size_t>(case_id % 17);
    const RandomLetters p = random_letters(rng, k, 50 + static_cast<std::size_t>(case_id) * 13,
                                           40 + static_cast<std::size_t>(case_id) * 17, -5);
    const align::LetterScores letters{p.a, p.b, p.matrix, k};
    AlignConfig c;
    c.gap_a = c.gap_b = static_cast<float>(1 + case_id % 4);
    c.max_alignments = 10;
    c.direction = case_id % 2 == 0 ? Direction::forward : Direction::reverse;
    if (case_id % 3 == 0) c.cap = 25.0F;
    const float scale = align::fast_scale(c);
    const auto want = scalar_on_quantized(letters.source(), c, scale);
    for (Isa isa : isas()) {
      expect_same(align::fast_local_alignments(letters, c, {0.0F, 1 + static_cast<unsigned>(case_id % 2), isa}), want,
                  describe(case_id, c, scale, isa, 1));
      const float best = align::fast_best_score(letters, c, {0.0F, 2, isa});
      EXPECT_EQ(best, want.empty() ? 0.0F : want.front().score) << "case " << case_id;
    }
  }
}

// Letters wide enough for several strips, at scales that keep the fill in int8 lanes (1) or move it to
// int16 lanes within the first rows (16, 64): the profile's layouts are built on first use, by whichever
// strip asks first, and int16 rows read the int8 layout when the scores fit it.
TEST(FastAlignment, LetterScoresAcrossStripsAndWidths) {
  std::mt19937 rng(31);
  for (int case_id = 0; case_id < 6; ++case_id) {
    const std::size_t k = 20;
    RandomLetters p = random_letters(rng, k, 150 + static_cast<std::size_t>(case_id) * 40,
                                     2100 + static_cast<std::size_t>(case_id) * 333, -4);
    for (std::size_t y = 0; y < p.b.size(); y += 97)
      std::copy(p.a.begin(), p.a.begin() + 40, p.b.begin() + static_cast<std::ptrdiff_t>(y / 2));
    const align::LetterScores letters{p.a, p.b, p.matrix, k};
    AlignConfig c;
    c.gap_a = c.gap_b = static_cast<float>(2 + case_id % 3);
    c.max_alignments = 5;
    c.direction = case_id % 2 == 0 ? Direction::forward : Direction::reverse;
    const float scale = case_id < 2 ? 1.0F : (case_id < 4 ? 16.0F : 64.0F);
    const auto want = scalar_on_quantized(letters.source(), c, scale);
    for (Isa isa : isas()) {
      for (unsigned threads : {1U, 3U}) {
        expect_same(align::fast_local_alignments(letters, c, {scale, threads, isa}), want,
                    describe(case_id, c, scale, isa, threads));
        EXPECT_EQ(align::fast_best_score(letters, c, {scale, threads, isa}), want.empty() ? 0.0F : want.front().score)
            << describe(case_id, c, scale, isa, threads);
      }
    }
  }
}

TEST(FastAlignment, BestScoreIsTheFirstAlignmentsScore) {
  std::mt19937 rng(13);
  for (int case_id = 0; case_id < 300; ++case_id) {
    auto p = test_support::random_problem(rng, 60);
    p.naive.config.threshold = 0;
    const float scale = align::fast_scale(p.naive.config, {8.0F, 1, Isa::best});
    auto one = p.naive.config;
    one.max_alignments = 1;
    const auto want = scalar_on_quantized(p.source(), one, scale);
    for (Isa isa : isas()) {
      EXPECT_EQ(align::fast_best_score(p.source(), p.naive.config, {8.0F, 1, isa}),
                want.empty() ? 0.0F : want.front().score)
          << "case " << case_id;
    }
  }
}

TEST(FastAlignment, QuantizationOfSpecialValuesMatchesEveryIsa) {
  // Ties (x.5 rounds to even), values beyond int16 (saturate), infinities and NaN (-32767 steps):
  // the vector quantizers must agree with the scalar rule that quantized() applies.
  std::mt19937 rng(17);
  const float specials[] = {0.5F,
                            1.5F,
                            2.5F,
                            -0.5F,
                            -2.5F,
                            1e30F,
                            -1e30F,
                            40000.0F,
                            -40000.0F,
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            3.0F,
                            7.0F,
                            32767.4F,
                            32767.6F};
  std::uniform_int_distribution<int> pick(0, 15);
  for (int case_id = 0; case_id < 60; ++case_id) {
    const std::size_t rows = 5 + static_cast<std::size_t>(case_id % 9),
                      cols = 9 + static_cast<std::size_t>(case_id) % 40;
    std::vector<float> s(rows * cols);
    for (auto& v : s) v = specials[pick(rng)];
    const auto source = ScoreSource::dense(s, rows, cols);
    AlignConfig c;
    c.cap = 30000.0F;
    c.gap_a = c.gap_b = 2.0F;
    c.direction = case_id % 2 == 0 ? Direction::forward : Direction::reverse;
    const auto want = scalar_on_quantized(source, c, 1.0F);
    for (Isa isa : isas())
      expect_same(align::fast_local_alignments(source, c, {1.0F, 1, isa}), want, describe(case_id, c, 1, isa, 1));
    const auto q = align::quantized(source, 1.0F);
    for (std::size_t i = 0; i < rows; ++i) {
      for (std::size_t j = 0; j < cols; ++j) {
        const float v = q.at(i, j), x = s[i * cols + j];
        if (std::isnan(x)) {
          EXPECT_EQ(v, -32767.0F);
        } else {
          EXPECT_EQ(v, std::nearbyint(std::clamp(x, -32767.0F, 32767.0F)));
        }
      }
    }
  }
}

TEST(FastAlignment, SaturationAndMisuse) {
  const std::size_t n = 300;
  std::vector<float> s(n * n, -1.0F);
  for (std::size_t i = 0; i < n; ++i) s[i * n + i] = 200.0F;  // 300 x 200 = 60000 steps at scale 1
  const auto source = ScoreSource::dense(s, n, n);
  AlignConfig c;
  // Without a cap the cumulative score leaves int16: a clear error, never a wrong alignment.
  EXPECT_THROW(align::fast_local_alignments(source, c, {1.0F, 1, Isa::best}), std::invalid_argument);
  EXPECT_THROW(align::fast_best_score(source, c, {1.0F, 1, Isa::scalar}), std::invalid_argument);
  // A smaller scale fits: 300 x 200 x 0.5 = 30000 steps.
  const auto fits = align::fast_local_alignments(source, c, {0.5F, 1, Isa::best});
  ASSERT_EQ(fits.size(), 1U);
  EXPECT_EQ(fits[0].score, 60000.0F);
  // With a cap saturation is harmless; the cap itself must fit in int16 steps.
  c.cap = 32767.0F;
  expect_same(align::fast_local_alignments(source, c, {1.0F, 2, Isa::best}), scalar_on_quantized(source, c, 1.0F),
              "cap at the int16 limit");
  c.cap = 40000.0F;
  EXPECT_THROW(align::fast_local_alignments(source, c, {1.0F, 1, Isa::best}), std::invalid_argument);
  c.cap = 0.2F;
  EXPECT_THROW(align::fast_local_alignments(source, c, {1.0F, 1, Isa::best}), std::invalid_argument);
  c.cap = 40.0F;
  EXPECT_EQ(align::fast_scale(c), 512.0F);  // the documented example
  EXPECT_THROW(align::fast_local_alignments(source, c, {-1.0F, 1, Isa::best}), std::invalid_argument);
  EXPECT_THROW(align::fast_local_alignments(source, c, {std::nanf(""), 1, Isa::best}), std::invalid_argument);
  c.gap_a = -1.0F;
  EXPECT_THROW(align::fast_local_alignments(source, c), std::invalid_argument);
  c.gap_a = 1.0F;
  c.self = true;
  EXPECT_THROW(align::fast_local_alignments(ScoreSource::dense(std::span<const float>(s.data(), 6), 2, 3), c),
               std::invalid_argument);
  std::vector<std::uint8_t> a{0, 1, 5};
  std::vector<float> matrix(4, 1.0F);
  EXPECT_THROW(align::fast_local_alignments(align::LetterScores{a, a, matrix, 2}, c), std::invalid_argument);
  // nothing to align is a normal, empty result
  EXPECT_TRUE(align::fast_local_alignments(ScoreSource::dense(std::span<const float>{}, 0, 0), AlignConfig{}).empty());
}

TEST(FastAlignment, ReadsEachScoreRowSegmentOnlyWhereTheRegionIs) {
  // A self pass never asks for scores outside its triangle: the source throws if it is asked.
  const std::size_t n = 200, sep = 7;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> small(-3, 2);
  std::vector<float> s(n * n);
  for (auto& v : s) v = static_cast<float>(small(rng));
  for (Direction d : {Direction::forward, Direction::reverse}) {
    const ScoreSource guarded(n, n, [&](std::size_t i, std::size_t j0, std::size_t j1, float* out) {
      for (std::size_t j = j0; j < j1; ++j) {
        if (i < j + sep) throw std::logic_error("read outside the self region");
        *out++ = s[i * n + j];
      }
    });
    AlignConfig c;
    c.self = true;
    c.min_separation = sep;
    c.direction = d;
    c.cap = 6.0F;
    c.max_alignments = 30;
    const auto got = align::fast_local_alignments(guarded, c, {1.0F, 2, Isa::best});
    expect_same(got, scalar_on_quantized(ScoreSource::dense(s, n, n), c, 1.0F), "guarded self pass");
  }
}

// The striped fill's edges (src/align/fast_striped_body.hpp): widths around the lanes (8 to 32), a tile
// (32), a block (256 to 1024) and a strip unit (512 / 1024), shorter than one vector, gaps 0 to 3, with
// and without cap, self triangles whose edge crosses blocks; every ISA and 1 to 4 threads.
TEST(FastAlignment, StripedFillEdgesEveryIsaAndThreads) {
  std::mt19937 rng(41);
  const std::size_t widths[] = {1,   3,   7,   8,   9,   15,  16,   17,   31,   32,   33,
                                255, 256, 257, 511, 512, 513, 1023, 1024, 1025, 2047, 2049};
  std::uniform_int_distribution<int> small(-3, 3);
  const float gaps[] = {0.0F, 0.5F, 1.0F, 3.0F};
  int case_id = 0;
  for (std::size_t n : widths) {
    for (int variant = 0; variant < 3; ++variant, ++case_id) {
      const bool self = variant == 2 && n <= 1025;
      const std::size_t m = self ? n : 1 + rng() % 75;
      std::vector<float> s(m * n);
      const std::size_t offset = rng() % (n + 1);
      for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = 0; j < n; ++j) {
          s[i * n + j] = variant == 1 && j == (i + offset) % n ? 2.0F : static_cast<float>(small(rng)) * 0.5F;
        }
      }
      if (self) {
        for (std::size_t i = 0; i < m; ++i) {
          for (std::size_t j = 0; j < i; ++j) s[j * n + i] = s[i * n + j];
        }
      }
      const auto source = ScoreSource::dense(s, m, n);
      AlignConfig c;
      c.gap_a = gaps[rng() % 4];
      c.gap_b = gaps[rng() % 4];
      if (rng() % 2) c.cap = static_cast<float>(1 + rng() % 12);
      c.threshold = 1.0F;
      c.max_alignments = 12;
      c.self = self;
      c.min_separation = 1 + rng() % 40;
      c.direction = rng() % 2 ? Direction::forward : Direction::reverse;
      const float scale = c.cap ? 0.0F : static_cast<float>(1 << (rng() % 4));  // cap: a large scale, int16
      const float used = align::fast_scale(c, {scale, 1, Isa::best});
      const auto want = scalar_on_quantized(source, c, used);
      for (Isa isa : isas()) {
        for (unsigned threads = 1; threads <= (n >= 1024 ? 4U : 1U); ++threads) {
          expect_same(align::fast_local_alignments(source, c, {scale, threads, isa}), want,
                      describe(case_id, c, used, isa, threads) + ", " + std::to_string(m) + " x " + std::to_string(n));
        }
        const float best = align::fast_best_score(source, c, {scale, 2, isa});  // the threshold does not apply
        if (want.empty()) {
          EXPECT_LT(best, c.threshold) << describe(case_id, c, used, isa, 2);
        } else {
          EXPECT_EQ(best, want.front().score) << describe(case_id, c, used, isa, 2);
        }
      }
      if (::testing::Test::HasFailure()) return;
    }
  }
}

// Gap steps of 0 and 1 with scores far above them: F from one cell reaches across many tiles and blocks
// (the lazy-F corrections, and the lane scan of every block), and with gap_b = 0 it never decays.
TEST(FastAlignment, FarReachingHorizontalGapsAndGapZero) {
  std::mt19937 rng(8);
  const std::size_t m = 90, n = 2300;
  for (int case_id = 0; case_id < 8; ++case_id) {
    std::vector<float> s(m * n, -4.0F);
    for (int k = 0; k < 6; ++k) s[(rng() % m) * n + rng() % n] = 30.0F;     // isolated peaks
    for (std::size_t i = 0; i < 20; ++i) s[(40 + i) * n + 700 + i] = 3.0F;  // and one diagonal
    const auto source = ScoreSource::dense(s, m, n);
    AlignConfig c;
    c.gap_b = case_id % 2 == 0 ? 0.0F : 0.0625F;
    c.gap_a = case_id % 4 < 2 ? 0.0F : 2.0F;
    if (case_id >= 4) c.cap = 50.0F;
    c.threshold = 1.0F;
    c.max_alignments = 10;
    c.direction = case_id % 3 == 0 ? Direction::reverse : Direction::forward;
    const float scale = c.cap ? 0.0F : 16.0F;  // gap_b 0.0625 is one step
    const float used = align::fast_scale(c, {scale, 1, Isa::best});
    const auto want = scalar_on_quantized(source, c, used);
    ASSERT_FALSE(want.empty());
    for (Isa isa : isas()) {
      for (unsigned threads : {1U, 3U}) {
        expect_same(align::fast_local_alignments(source, c, {scale, threads, isa}), want,
                    describe(case_id, c, used, isa, threads));
      }
    }
  }
}

// The int8 lanes (H - 128 in int8, so H in [0, 255]): exact while the cap is below 255 steps, else until
// a row reaches 255 steps, and only for gaps <= 127 steps and scores in [-128, 127]; a strip goes on in
// int16 from the first row that breaks a rule. Best values right at the limit and beyond, caps at it,
// scores and gaps beyond int8, and strips of which only one saturates (its neighbour then sees left
// values beyond int8).
TEST(FastAlignment, Int8LanesAtTheirLimits) {
  const std::size_t m = 270, n = 2100;
  int case_id = 0;
  for (std::size_t run : {127U, 254U, 255U, 256U, 260U}) {
    for (int layout = 0; layout < 4; ++layout, ++case_id) {
      // a diagonal run of +1 (best = run length) in the left strip, the right strip, across all, or
      // ending at the last column of the first strip (1024 with 2 threads, for both ISAs' units)
      std::vector<float> s(m * n, -3.0F);
      const std::size_t j0 = layout == 0 ? 10 : (layout == 1 ? n - 280 : (layout == 2 ? 1000 : 1024 - run));
      for (std::size_t k = 0; k < run; ++k) s[k * n + j0 + k] = 1.0F;  // run < m
      if (layout == 2) {
        s[5 * n + 2000] = 200.0F;   // a score beyond int8
        s[6 * n + 2001] = -200.0F;  // and one below it
      }
      const auto source = ScoreSource::dense(s, m, n);
      for (int config = 0; config < 6; ++config) {
        AlignConfig c;
        const float gaps[] = {1.0F, 1.0F, 4.0F, 150.0F, 127.0F, 128.0F};  // steps at scale 1
        c.gap_a = c.gap_b = gaps[config];
        if (config == 1) c.cap = static_cast<float>(254 + case_id % 3);  // 254, 255, 256
        if (config == 3) c.cap = 100.0F;
        if (config == 4) c.cap = 250.0F;
        c.threshold = 1.0F;
        c.max_alignments = 4;
        const auto want = scalar_on_quantized(source, c, 1.0F);
        ASSERT_FALSE(want.empty());
        for (Isa isa : isas()) {
          for (unsigned threads : {1U, 2U}) {
            const auto what = describe(case_id * 6 + config, c, 1.0F, isa, threads) + ", run " + std::to_string(run);
            expect_same(align::fast_local_alignments(source, c, {1.0F, threads, isa}), want, what);
            EXPECT_EQ(align::fast_best_score(source, c, {1.0F, threads, isa}), want.front().score) << what;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace seqtopo
