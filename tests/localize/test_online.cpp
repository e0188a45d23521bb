// The online localizer against a naive full-table Smith-Waterman on the frames seen so far, against the
// alignment engine itself, and on planted paths.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "seqtopo/align/smith_waterman.hpp"
#include "seqtopo/localize/online_localizer.hpp"

namespace seqtopo::localize {
namespace {

// The whole forward (or reverse) table of the first `rows` query frames, textbook recurrence.
std::vector<std::vector<float>> naive_table(const SimilarityMatrix& scores, std::size_t rows, bool reverse, float gap,
                                            std::optional<float> cap) {
  const std::size_t m = scores.cols;
  std::vector<std::vector<float>> h(rows + 1, std::vector<float>(m + 2, 0.0F));  // map j at index j + 1
  for (std::size_t i = 1; i <= rows; ++i) {
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t j = reverse ? m - 1 - k : k;
      const std::size_t col = j + 1;
      const float diag = reverse ? h[i - 1][col + 1] : h[i - 1][col - 1];
      const float side = reverse ? h[i][col + 1] : h[i][col - 1];
      float v = std::max({0.0F, diag + scores(i - 1, j), h[i - 1][col] - gap, side - gap});
      if (cap) v = std::min(v, *cap);
      h[i][col] = v;
    }
  }
  return h;
}

SimilarityMatrix random_matrix(std::size_t rows, std::size_t cols, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0F, 1.0F);
  SimilarityMatrix s(rows, cols);
  for (auto& v : s.values) v = u(rng);
  return s;
}

TEST(Online, EqualsNaiveTablesOnTheFramesSeenSoFar) {
  std::mt19937 rng(11);
  for (int round = 0; round < 30; ++round) {
    const auto s = random_matrix(5 + rng() % 25, 3 + rng() % 30, rng);
    LocalizeConfig c;
    c.enhance = round % 2 == 0;
    c.score.contrast_offset = c.enhance ? 0.8F : -0.1F;
    c.search.gap = 0.3F + 0.1F * static_cast<float>(rng() % 10);
    if (round % 3 == 0) c.search.cap = 2.5F;
    c.significance.threshold = 1.0F;
    const auto scores = score_matrix(s, c);
    const auto fwd = naive_table(scores, s.rows, false, c.search.gap, c.search.cap);
    const auto rev = naive_table(scores, s.rows, true, c.search.gap, c.search.cap);
    OnlineLocalizer online(s.cols, c);
    for (std::size_t i = 0; i < s.rows; ++i) {
      const auto e = online.feed(s.row(i));
      EXPECT_EQ(e.query, i);
      float best = -1;
      std::size_t best_j = 0;
      align::Direction best_d = align::Direction::forward;
      for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t j = 0; j < s.cols; ++j) {
          const float v = pass == 0 ? fwd[i + 1][j + 1] : rev[i + 1][j + 1];
          ASSERT_FLOAT_EQ(pass == 0 ? online.forward_row()[j] : online.reverse_row()[j], v) << i << " " << j;
          if (v > best || (v == best && scores(i, j) > scores(i, best_j))) {
            best = v;
            best_j = j;
            best_d = pass == 0 ? align::Direction::forward : align::Direction::reverse;
          }
        }
      }
      EXPECT_FLOAT_EQ(e.score, best);
      EXPECT_EQ(e.map, best_j) << i;
      EXPECT_EQ(e.direction, best_d) << i;
      EXPECT_GE(e.confidence, 0.0);
      EXPECT_LE(e.confidence, 1.0);
      EXPECT_EQ(e.in_map, e.confidence >= c.min_confidence && e.confidence > 0);
    }
  }
}

TEST(Online, EstimatesNeverDependOnLaterFrames) {
  std::mt19937 rng(12);
  const auto s = random_matrix(40, 25, rng);
  LocalizeConfig c;
  const auto all = online_estimates(s, c);
  for (std::size_t t = 1; t <= s.rows; t += 7) {
    SimilarityMatrix prefix(
        t, s.cols, std::vector<float>(s.values.begin(), s.values.begin() + static_cast<std::ptrdiff_t>(t * s.cols)));
    const auto part = online_estimates(prefix, c);
    for (std::size_t i = 0; i < t; ++i) {
      EXPECT_EQ(part[i].map, all[i].map);
      EXPECT_EQ(part[i].score, all[i].score);
      EXPECT_EQ(part[i].confidence, all[i].confidence);
      EXPECT_EQ(part[i].direction, all[i].direction);
    }
  }
}

TEST(Online, BestConfidenceSoFarIsTheEnginesBestAlignmentScore) {
  // The engine's first alignment ends at the highest cell of its table; the online rows are that table's
  // rows, so on every prefix the highest confidence seen equals the engine's best score.
  std::mt19937 rng(13);
  for (int round = 0; round < 20; ++round) {
    const auto s = random_matrix(4 + rng() % 20, 4 + rng() % 20, rng);
    LocalizeConfig c;
    c.enhance = false;
    c.score.contrast_offset = -0.15F;
    c.search.gap = 0.6F;
    c.search.reverse = round % 2 == 0;
    if (round % 4 == 1) c.search.cap = 1.5F;
    const auto scores = score_matrix(s, c);
    OnlineLocalizer online(s.cols, c);
    float best_so_far = 0;
    for (std::size_t i = 0; i < s.rows; ++i) {
      best_so_far = std::max(best_so_far, online.feed(s.row(i)).score);
      align::AlignConfig ac;
      ac.gap_a = ac.gap_b = c.search.gap;
      ac.cap = c.search.cap;
      ac.max_alignments = 1;
      const auto source =
          align::ScoreSource::dense(std::span<const float>(scores.values.data(), (i + 1) * s.cols), i + 1, s.cols);
      const auto engine =
          c.search.reverse ? align::local_alignments_both(source, ac, 1) : align::local_alignments(source, ac);
      const float expected = engine.empty() ? 0.0F : engine.front().score;
      EXPECT_FLOAT_EQ(best_so_far, expected) << "round " << round << " frame " << i;
    }
  }
}

TEST(Online, FollowsPlantedPathsInBothDirections) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<float> u(0.0F, 0.5F);
  SimilarityMatrix s(80, 120);
  for (auto& v : s.values) v = u(rng);
  for (std::size_t q = 0; q < 40; ++q) s(q, 20 + q) = 1.0F;    // forward along map 20..59
  for (std::size_t q = 40; q < 80; ++q) s(q, 159 - q) = 1.0F;  // then backwards along map 119..80
  LocalizeConfig c;
  c.enhance = false;
  c.score.contrast_offset = 0.6F;
  c.search.gap = 0.5F;
  c.significance.threshold = 2.0F;
  c.search.cap = 5.0F;  // the cap lets the forward evidence fade quickly after the turn
  OnlineLocalizer online(s.cols, c);
  for (std::size_t q = 0; q < s.rows; ++q) {
    const auto e = online.feed(s.row(q));
    if (q < 5 || (q >= 40 && q < 52)) continue;  // warm-up after the start and after the turn
    ASSERT_TRUE(e.in_map) << q;
    EXPECT_EQ(e.map, q < 40 ? 20 + q : 159 - q) << q;
    EXPECT_EQ(e.direction, q < 40 ? align::Direction::forward : align::Direction::reverse) << q;
  }
}

// Frames of little information online, as offline (LowInformationFrames): query frames 40-79 are dark where the map
// was lit, the map is dark at 140-179. Told which frames are dark, the localizer's estimates are those of the same
// rows with every score of a dark frame capped at 0 (without enhancement: the similarity capped at the offset), told
// nothing; and none of its confident answers lies in the map's dark stretch. The map's frames come before the query.
TEST(Online, FramesOfLittleInformationAreScoredAtMostZero) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> u(0.0F, 0.5F);
  SimilarityMatrix s(120, 200);
  for (auto& v : s.values) v = u(rng);
  for (std::size_t q = 0; q < 120; ++q) s(q, q + 10) = q >= 40 && q < 80 ? 0.2F : 1.0F;
  for (std::size_t q = 40; q < 80; ++q) {
    for (std::size_t m = 140; m < 180; ++m) s(q, m) = 0.95F;
  }
  LocalizeConfig c;
  c.enhance = false;
  c.score.contrast_offset = 0.6F;
  c.search.gap = 0.5F;
  c.significance.threshold = 2.0F;
  const auto dark_query = [](std::size_t q) { return q >= 40 && q < 80; };
  const auto dark_map = [](std::size_t m) { return m >= 140 && m < 180; };
  SimilarityMatrix capped = s;
  for (std::size_t q = 0; q < s.rows; ++q) {
    for (std::size_t m = 0; m < s.cols; ++m) {
      if (dark_query(q) || dark_map(m)) capped(q, m) = std::min(capped(q, m), c.score.contrast_offset);
    }
  }
  OnlineLocalizer told(s.cols, c), plain(s.cols, c);
  std::vector<std::size_t> map_dark;
  for (std::size_t m = 0; m < s.cols; ++m) {
    if (dark_map(m)) map_dark.push_back(m);
  }
  told.set_low_information_map(map_dark);
  EXPECT_THROW(told.set_low_information_map(std::vector<std::size_t>{200}), std::invalid_argument);
  for (std::size_t q = 0; q < s.rows; ++q) {
    const std::span<const float> row = s.row(q);
    const auto e = told.feed_descriptors(std::span<const std::span<const float>>(&row, 1), dark_query(q));
    const auto expected = plain.feed(capped.row(q));
    ASSERT_EQ(e.map, expected.map) << q;
    ASSERT_EQ(e.score, expected.score) << q;
    ASSERT_EQ(e.confidence, expected.confidence) << q;
    EXPECT_FALSE(e.in_map && dark_map(e.map)) << q;
  }
  EXPECT_THROW(told.set_low_information_map(map_dark), std::invalid_argument);
}

// Brute force of the fixed-lag smoother's score: the best alignment through (k, j) using rows up to `last`, as the
// table value plus the best path that starts with a matched pair after it, every later pair tried (no recurrence
// shared with the localizer).
float through_score(const SimilarityMatrix& scores, const std::vector<std::vector<float>>& table, std::size_t k,
                    std::size_t j, std::size_t last, bool reverse, float gap) {
  const std::size_t m = scores.cols;
  const float f = table[k + 1][j + 1];
  if (!(f > 0)) return f;
  // P[r][c]: the best path whose first matched pair is (r, c), within rows <= last.
  std::vector<std::vector<float>> p(last + 1, std::vector<float>(m, 0.0F));
  const auto after = [&](std::size_t r, std::size_t c) {  // max(0, best path starting strictly after (r, c))
    float best = 0;
    for (std::size_t r2 = r + 1; r2 <= last; ++r2) {
      for (std::size_t c2 = 0; c2 < m; ++c2) {
        if (reverse ? c2 >= c : c2 <= c) continue;
        const auto skipped = static_cast<float>((r2 - r - 1) + (reverse ? c - c2 - 1 : c2 - c - 1));
        best = std::max(best, p[r2][c2] - gap * skipped);
      }
    }
    return best;
  };
  for (std::size_t r = last; r > k; --r) {
    for (std::size_t c = 0; c < m; ++c) p[r][c] = scores(r, c) + after(r, c);
  }
  return f + after(k, j);
}

TEST(Online, FixedLagSmoothingScoresTheBestAlignmentThroughTheFrame) {
  std::mt19937 rng(5);
  for (int round = 0; round < 24; ++round) {
    const auto s = random_matrix(6 + rng() % 14, 3 + rng() % 12, rng);
    LocalizeConfig c;
    c.score.contrast_offset = 0.3F;
    c.search.gap = 0.2F + 0.1F * static_cast<float>(rng() % 8);
    c.search.reverse = round % 2 == 0;
    c.significance.threshold = 1.0F;
    c.lag = 1 + rng() % 5;
    const auto scores = score_matrix(s, c);
    const auto fwd = naive_table(scores, s.rows, false, c.search.gap, std::nullopt);
    const auto rev = naive_table(scores, s.rows, true, c.search.gap, std::nullopt);
    OnlineLocalizer online(s.cols, c);
    for (std::size_t i = 0; i < s.rows; ++i) {
      const auto now = online.feed(s.row(i));
      const auto same = online.smoothed(i);  // no later frame: the frame's own estimate
      EXPECT_EQ(same.map, now.map);
      EXPECT_EQ(same.score, now.score);
      EXPECT_EQ(same.confidence, now.confidence);
      for (std::size_t k = i > c.lag ? i - c.lag : 0; k < i; ++k) {
        const auto e = online.smoothed(k);
        EXPECT_EQ(e.query, k);
        float best = 0;
        for (std::size_t j = 0; j < s.cols; ++j) {
          best = std::max(best, through_score(scores, fwd, k, j, i, false, c.search.gap));
          if (c.search.reverse) best = std::max(best, through_score(scores, rev, k, j, i, true, c.search.gap));
        }
        EXPECT_NEAR(e.score, best, 1e-4F * std::max(1.0F, best)) << "round " << round << " frame " << k << " of " << i;
        const bool backwards = e.direction == align::Direction::reverse;
        EXPECT_NEAR(through_score(scores, backwards ? rev : fwd, k, e.map, i, backwards, c.search.gap), e.score,
                    1e-4F * std::max(1.0F, best));
        EXPECT_GE(e.confidence, 0.0);
        EXPECT_LE(e.confidence, 1.0);
      }
      if (i > c.lag) {
        EXPECT_THROW((void)online.smoothed(i - c.lag - 1), std::out_of_range);
      }
    }
    EXPECT_THROW((void)online.smoothed(s.rows), std::out_of_range);
  }
}

// The smoother finds the planted path's frames that the filter, without the later frames, cannot tell yet.
TEST(Online, FixedLagSmoothingRecoversTheFramesAtTheStartOfARevisit) {
  std::mt19937 rng(3);
  const std::size_t n = 60, m = 80, offset = 12;
  std::normal_distribution<float> noise(0.0F, 1.0F);
  SimilarityMatrix s(n, m);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < m; ++j) s(i, j) = noise(rng) + (j == i + offset ? 1.2F : 0.0F);
  }
  LocalizeConfig filter, smoother;
  smoother.lag = 10;
  OnlineLocalizer now(m, filter), late(m, smoother);
  std::size_t right_now = 0, right_late = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto e = now.feed(s.row(i));
    late.feed(s.row(i));
    right_now += e.map + 2 >= i + offset && e.map <= i + offset + 2;
    const auto check = [&](std::size_t k) {
      const auto l = late.smoothed(k);
      right_late += l.map + 2 >= k + offset && l.map <= k + offset + 2;
    };
    if (i >= smoother.lag) check(i - smoother.lag);
    if (i + 1 == n) {
      for (std::size_t k = n - smoother.lag; k < n; ++k) check(k);
    }
  }
  EXPECT_GT(right_late, right_now + 3) << right_now << " of " << n << " at once, " << right_late << " with the lag";
}

// The query drives the whole map and on past its end (a route longer than the map): past the end the table keeps
// the revisit's value, falling by a gap a frame, and a chance matched pair in the map's last frames now and then ends
// a path there. Such a frame is past its path's maximum by the gaps it took, and is not confident; the frames along
// the map are. Eight seeds, 60 map frames, 40 query frames past them.
TEST(Online, FramesPastTheEndOfTheMapAreNotConfident) {
  const std::size_t m = 60, n = 100;
  std::size_t confident_past = 0, confident_on = 0, on = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0F, 1.0F);
    SimilarityMatrix s(n, m);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < m; ++j) s(i, j) = noise(rng) + (i == j ? 2.0F : 0.0F);
    }
    for (const std::size_t lag : {0, 10}) {
      LocalizeConfig c;
      c.lag = lag;
      OnlineLocalizer localizer(m, c);
      for (std::size_t i = 0; i < n; ++i) {
        localizer.feed(s.row(i));
        if (i < lag) continue;
        const std::size_t k = i - lag;
        const auto answer = [&](std::size_t frame) {
          const auto e = localizer.smoothed(frame);
          if (frame >= m + 2) {
            confident_past += e.confidence >= 0.5;
          } else if (frame >= 10) {
            ++on;
            confident_on += e.confidence >= 0.5 && e.map + 2 >= frame && e.map <= frame + 2;
          }
        };
        answer(k);
        if (i + 1 == n) {
          for (std::size_t later = k + 1; later < n; ++later) answer(later);
        }
      }
    }
  }
  EXPECT_EQ(confident_past, 0U);
  EXPECT_GT(confident_on, on * 9 / 10) << confident_on << " of " << on;
}

TEST(Online, RejectsBadInput) {
  EXPECT_THROW(OnlineLocalizer(0), std::invalid_argument);
  LocalizeConfig bad;
  bad.search.gap = std::nanf("");
  EXPECT_THROW(OnlineLocalizer(3, bad), std::invalid_argument);
  LocalizeConfig too_late;  // a lag's answers cost lag x map frames each
  too_late.lag = kMaxLag + 1;
  EXPECT_THROW(OnlineLocalizer(3, too_late), std::invalid_argument);
  too_late.lag = kMaxLag;
  EXPECT_NO_THROW(OnlineLocalizer(3, too_late));
  OnlineLocalizer online(3);
  const std::vector<float> short_row{1.0F, 2.0F};
  EXPECT_THROW(online.feed(short_row), std::invalid_argument);
  const std::vector<float> nan_row{1.0F, std::nanf(""), 0.0F};
  EXPECT_THROW(online.feed(nan_row), std::invalid_argument);
  EXPECT_EQ(online.frames_seen(), 0U);
  EXPECT_THROW(online_estimates(SimilarityMatrix{}), std::invalid_argument);
}

}  // namespace
}  // namespace seqtopo::localize
