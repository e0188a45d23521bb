// The fill's striped kernels (src/align/fast_kernels.hpp) against the scalar row kernel, row by row, on
// one column strip: every cell, the row maximum, the tiles' maxima and their right columns, for strips
// of every width around the lane, vector, tile and block sizes, gaps 0 to beyond the element range,
// caps in and out of int8, searched regions that grow from either side, and a left column of values.
// White-box: it drives the kernels the way FastPass::fill_striped does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "../../src/align/fast_kernels.hpp"

namespace seqtopo {
namespace {

using align::detail::kTileSide;
using align::detail::striped_index;
using align::detail::StripedJob;
using Step = std::int16_t;

struct StripedIsa {
  const char* name;
  std::size_t lanes16, lanes8;
  align::detail::StripedKernel striped16, striped8;
  align::detail::BlockStriper16 stripe16;
  align::detail::BlockStriper8 stripe8;
  align::detail::BlockDestriper16 destripe16;
  align::detail::BlockDestriper8 destripe8;
};

std::vector<StripedIsa> striped_isas() {
  std::vector<StripedIsa> out;
  const align::Isa best = align::best_isa();
  if (best == align::Isa::sse41 || best == align::Isa::avx2) {
    out.push_back({"sse4.1", 8, 16, align::detail::striped16_sse41, align::detail::striped8_sse41,
                   align::detail::stripe16_sse41, align::detail::stripe8_sse41, align::detail::destripe16_sse41,
                   align::detail::destripe8_sse41});
  }
  if (best == align::Isa::avx2) {
    out.push_back({"avx2", 16, 32, align::detail::striped16_avx2, align::detail::striped8_avx2,
                   align::detail::stripe16_avx2, align::detail::stripe8_avx2, align::detail::destripe16_avx2,
                   align::detail::destripe8_avx2});
  }
  return out;
}

std::int8_t saturate8(int v) { return static_cast<std::int8_t>(std::clamp(v, -128, 127)); }

TEST(FastStriped, BlockStripersAndDestripersTransposeEveryBlock) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> value(-32768, 32767);
  for (const auto& isa : striped_isas()) {
    for (bool bytes : {false, true}) {
      const std::size_t lanes = bytes ? isa.lanes8 : isa.lanes16, block = kTileSide * lanes;
      std::vector<Step> in(block);
      for (auto& v : in) v = static_cast<Step>(bytes && rng() % 2 ? value(rng) % 200 : value(rng));
      std::vector<Step> out16(block);
      std::vector<std::int8_t> out8(block);
      if (bytes) {
        isa.stripe8(in.data(), out8.data());
      } else {
        isa.stripe16(in.data(), out16.data());
      }
      for (std::size_t rel = 0; rel < block; ++rel) {
        const std::size_t at = striped_index(rel, lanes);
        if (bytes) {
          ASSERT_EQ(out8[at], saturate8(in[rel])) << isa.name << " int8, column " << rel;
        } else {
          ASSERT_EQ(out16[at], in[rel]) << isa.name << " int16, column " << rel;
        }
      }
      // and back, as H (int8 rows hold H - 128)
      std::vector<Step> back(block);
      if (bytes) {
        isa.destripe8(out8.data(), back.data());
      } else {
        isa.destripe16(out16.data(), back.data());
      }
      for (std::size_t rel = 0; rel < block; ++rel) {
        const int want = bytes ? saturate8(in[rel]) + align::detail::kInt8Offset : in[rel];
        ASSERT_EQ(back[rel], want) << isa.name << (bytes ? " int8" : " int16") << " back, column " << rel;
      }
    }
  }
}

// One strip of `width` columns over `rows` rows, computed by the reference (the scalar row kernel on
// natural rows) and by one striped kernel; compares everything the fill keeps.
struct StripCase {
  std::size_t width = 0, rows = 0;
  Step gap_a = 0, gap_b = 0, cap = 32767;
  enum Region { full, growing_right, growing_left } region = full;
  std::vector<std::vector<Step>> scores;                      // [row][column], natural
  std::vector<Step> left;                                     // H(i, lo - 1) for i = 0 .. rows (left[0] = 0)
  std::vector<std::pair<std::size_t, std::size_t>> searched;  // per row i >= 1: [rlo, rhi), rlo < rhi
};

StripCase random_case(std::mt19937& rng, std::size_t width, std::size_t rows, int kind) {
  StripCase c;
  c.width = width;
  c.rows = rows;
  const Step gaps[] = {0, 1, 2, 3, 7, 50, 127, 128, 200, 32767};
  c.gap_a = gaps[rng() % 10];
  c.gap_b = rng() % 3 == 0 ? c.gap_a : gaps[rng() % 7];  // mostly small: F reaches far
  const Step caps[] = {1, 6, 100, 126, 127, 128, 254, 255, 256, 1000, 30000, 32767};
  c.cap = caps[rng() % 12];
  c.region = static_cast<StripCase::Region>(rng() % 3);
  // kind 0: small scores (many ties, long F); 1: a planted diagonal on a poor background; 2: extremes
  std::uniform_int_distribution<int> small(-3, 3), extreme(-32768, 32767);
  c.scores.assign(rows + 1, std::vector<Step>(width, 0));
  const std::size_t offset = rng() % (width + 1);
  for (std::size_t i = 1; i <= rows; ++i) {
    for (std::size_t j = 0; j < width; ++j) {
      int v = small(rng);
      if (kind == 1) v = j == i + offset ? 40 : small(rng) - 2;
      if (kind == 2 && rng() % 4 == 0) v = rng() % 2 ? extreme(rng) % 200 : (rng() % 2 ? -32768 : 32767);
      if (kind == 2 && i % 2 == 0) v = std::clamp(v, -128, 127);  // rows an int8 kernel takes
      c.scores[i][j] = static_cast<Step>(v);
    }
  }
  c.left.assign(rows + 1, 0);
  for (std::size_t i = 1; i <= rows; ++i) {
    if (rng() % 2) c.left[i] = static_cast<Step>(rng() % (static_cast<unsigned>(c.cap) + 1));
  }
  // regions grow with i (as search_region's do), from an edge anywhere in the strip
  std::size_t edge = rng() % width;
  const std::size_t speed = 1 + rng() % 40;
  for (std::size_t i = 1; i <= rows; ++i) {
    if (c.region == StripCase::full) {
      c.searched.emplace_back(0, width);
    } else if (c.region == StripCase::growing_right) {
      c.searched.emplace_back(0, std::min(width, edge + 1));
      edge += speed;
    } else {
      c.searched.emplace_back(width - 1 - std::min(width - 1, edge), width);
      edge += speed;
    }
  }
  return c;
}

// The reference: natural rows of H, 0 outside the searched columns and at the strip's left column
// where the left boundary is outside (the fill passes H(i, lo - 1) as it is).
std::vector<std::vector<Step>> reference(const StripCase& c) {
  const std::size_t n = c.width;
  std::vector<std::vector<Step>> h(c.rows + 1, std::vector<Step>(n + 1 + align::detail::kRowPadding, 0));
  std::vector<Step> score(n + 1 + align::detail::kRowPadding, 0);
  for (std::size_t i = 1; i <= c.rows; ++i) {
    h[i - 1][0] = c.left[i - 1];
    h[i][0] = c.left[i];
    const auto [rlo, rhi] = c.searched[i - 1];
    std::copy(c.scores[i].begin(), c.scores[i].end(), score.begin() + 1);
    const std::size_t lo = rlo + 1, hi = rhi;  // 1-based
    align::detail::RowJob job{
        h[i - 1].data(), h[i].data(), score.data(), lo, hi, c.gap_a, c.gap_b, c.cap, lo == 1 ? c.left[i] : Step{0}};
    align::detail::row_scalar(job);
  }
  return h;
}

// Runs the striped kernel on the case and checks every row, up to the first that an int8 kernel may not
// take exactly (the fill would redo it in int16 and go on in int16). Counts the rows checked. With score8
// (int16 rows), the scores are given in the int8 layout (StripedJob::score8), up to the first row whose
// scores do not fit int8.
template <typename E>
void check_striped(const StripCase& c, const StripedIsa& isa, bool bytes, const std::string& what, std::size_t& checked,
                   bool score8 = false) {
  const std::size_t lanes = bytes ? isa.lanes8 : isa.lanes16, block = kTileSide * lanes;
  const std::size_t padded = (c.width + block - 1) / block * block, tiles = padded / kTileSide;
  const bool exact8 = c.cap < align::detail::kInt8Limit;
  if (bytes && std::max(c.gap_a, c.gap_b) > align::detail::kInt8Gap) return;
  const int offset = bytes ? align::detail::kInt8Offset : 0;  // int8 rows hold H - 128
  const auto want = reference(c);
  std::vector<E> rows(2 * padded, static_cast<E>(-offset)), score(padded, 0);
  const std::size_t block8 = kTileSide * isa.lanes8;
  std::vector<std::int8_t> scores8(score8 ? (c.width + block8 - 1) / block8 * block8 : 0, 0);
  std::vector<Step> tile_max(tiles, 0), want_tiles(tiles, 0),
      columns(tiles + 1, 0);  // 0 as the fill starts: untouched blocks write nothing
  int running = 0;
  std::size_t prev = 0;
  for (std::size_t i = 1; i <= c.rows; ++i) {
    for (std::size_t rel = 0; rel < c.width; ++rel) {
      const Step v = c.scores[i][rel];
      score[striped_index(rel, lanes)] = static_cast<E>(bytes ? saturate8(v) : v);
    }
    const auto [rlo, rhi] = c.searched[i - 1];
    const auto [low, high] = std::minmax_element(c.scores[i].begin() + static_cast<std::ptrdiff_t>(rlo),
                                                 c.scores[i].begin() + static_cast<std::ptrdiff_t>(rhi));
    if (bytes && (*low < -128 || *high > 127)) return;
    if (score8) {
      const auto [all_low, all_high] = std::minmax_element(c.scores[i].begin(), c.scores[i].end());
      if (*all_low < -128 || *all_high > 127) return;
      for (std::size_t rel = 0; rel < c.width; ++rel) {
        scores8[striped_index(rel, isa.lanes8)] = static_cast<std::int8_t>(c.scores[i][rel]);
      }
    }
    StripedJob job{rows.data() + prev * padded,
                   rows.data() + (1 - prev) * padded,
                   score.data(),
                   c.width,
                   rlo,
                   rhi,
                   c.left[i],
                   c.left[i - 1],
                   c.gap_a,
                   c.gap_b,
                   c.cap,
                   tile_max.data(),
                   columns.data()};
    if (score8) {
      job.score = scores8.data();
      job.score8 = true;
    }
    if (bytes && !exact8 && std::max(c.left[i], c.left[i - 1]) >= align::detail::kInt8Limit) return;
    const Step got_max = bytes ? isa.striped8(job) : isa.striped16(job);
    if (bytes && !exact8 && got_max >= align::detail::kInt8Limit) return;
    prev = 1 - prev;
    ++checked;
    const E* h = rows.data() + prev * padded;
    int row_max = 0;
    for (std::size_t rel = 0; rel < c.width; ++rel) {
      const Step expected = want[i][rel + 1];
      ASSERT_EQ(h[striped_index(rel, lanes)] + offset, expected)
          << what << ": row " << i << " column " << rel << " of " << c.width;
      row_max = std::max<int>(row_max, expected);
      Step& t = want_tiles[rel / kTileSide];
      t = std::max(t, expected);
    }
    running = std::max(running, row_max);
    // padding never exceeds a real cell above or left of it
    EXPECT_GE(got_max, row_max) << what << ": row " << i;
    EXPECT_LE(got_max, running) << what << ": row " << i;
    for (std::size_t q = 0; (q + 1) * kTileSide <= c.width; ++q) {
      ASSERT_EQ(columns[q], want[i][(q + 1) * kTileSide]) << what << ": row " << i << " right column of tile " << q;
    }
    if (i % kTileSide == 0 || i == c.rows) {  // the end of a band of tiles
      for (std::size_t t = 0; t * kTileSide < c.width; ++t) {
        ASSERT_EQ(tile_max[t], want_tiles[t]) << what << ": row " << i << " tile " << t;
      }
      std::fill(tile_max.begin(), tile_max.end(), Step{0});
      std::fill(want_tiles.begin(), want_tiles.end(), Step{0});
    }
  }
}

TEST(FastStriped, KernelsEqualTheScalarRowKernel) {
  std::mt19937 rng(2026);
  const std::size_t widths[] = {1,   2,   7,   8,   15,  16,  17,   31,   32,   33,   63,   64,   65,
                                255, 256, 257, 511, 512, 513, 1023, 1024, 1025, 1100, 2047, 2048, 2049};
  std::size_t cases = 0, rows16 = 0, rows16_score8 = 0, rows8 = 0, rows8_high = 0;
  for (int round = 0; round < 8; ++round) {
    for (std::size_t width : widths) {
      const std::size_t rows = 1 + rng() % 70;
      const StripCase c = random_case(rng, width, rows, round % 3);
      for (const auto& isa : striped_isas()) {
        for (bool bytes : {false, true}) {
          const std::string what = std::string(isa.name) + (bytes ? " int8" : " int16") + ", width " +
                                   std::to_string(width) + ", gaps " + std::to_string(c.gap_a) + "/" +
                                   std::to_string(c.gap_b) + ", cap " + std::to_string(c.cap) + ", region " +
                                   std::to_string(static_cast<int>(c.region)) + ", kind " + std::to_string(round % 3);
          if (bytes) {
            std::size_t checked = 0;
            check_striped<std::int8_t>(c, isa, true, what, checked);
            rows8 += checked;
            if (c.cap > 127) rows8_high += checked;  // values past signed int8
          } else {
            check_striped<std::int16_t>(c, isa, false, what, rows16);
            check_striped<std::int16_t>(c, isa, false, what + ", int8 scores", rows16_score8, true);
          }
          if (::testing::Test::HasFailure()) return;
          ++cases;
        }
      }
    }
  }
  if (!striped_isas().empty()) {
    EXPECT_GT(cases, 400U);
    EXPECT_GT(rows16, 5000U);
    EXPECT_GT(rows8, 2500U);
    EXPECT_GT(rows8_high, 500U);
    EXPECT_GT(rows16_score8, 2500U);
  }
  std::printf("rows checked: int16 %zu (%zu from int8 scores), int8 %zu (%zu with a cap beyond 127)\n", rows16,
              rows16_score8, rows8, rows8_high);
}

// F that must travel: one cell at the cap (or a high value) at the strip's left, mismatches everywhere,
// gap_b 0 or 1: F crosses every vector of every tile of every block, wrapping lanes many times.
TEST(FastStriped, FarTravellingFAcrossLanesAndBlocks) {
  for (const auto& isa : striped_isas()) {
    for (Step gap_b : {Step{0}, Step{1}, Step{2}}) {
      for (Step cap : {Step{100}, Step{250}, Step{3000}}) {
        for (bool from_left : {false, true}) {
          StripCase c;
          c.width = 3001;
          c.rows = 40;
          c.gap_a = 5;
          c.gap_b = gap_b;
          c.cap = cap;
          c.scores.assign(c.rows + 1, std::vector<Step>(c.width, -7));
          c.left.assign(c.rows + 1, 0);
          for (std::size_t i = 1; i <= c.rows; ++i) {
            c.searched.emplace_back(0, c.width);
            if (from_left) {
              c.left[i] = cap;  // from the strip on the left
            } else {
              c.scores[i][i % 5] = std::min<Step>(cap, 127);  // a peak near the left edge
              if (i > 1) c.scores[i][i % 5 + 1] = 127;        // on a short diagonal
            }
          }
          for (bool bytes : {false, true}) {
            const std::string what = std::string(isa.name) + (bytes ? " int8" : " int16") + ", gap_b " +
                                     std::to_string(gap_b) + ", cap " + std::to_string(cap) +
                                     (from_left ? ", from the left column" : ", from a peak");
            std::size_t checked = 0;
            if (bytes) {
              check_striped<std::int8_t>(c, isa, true, what, checked);
            } else {
              check_striped<std::int16_t>(c, isa, false, what, checked);
            }
            if (!bytes || cap < align::detail::kInt8Limit || !from_left) {
              EXPECT_GT(checked, 0U) << what;  // a left column beyond int8 is for int16 rows only
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace seqtopo
