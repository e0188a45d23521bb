#include "seqtopo/significance/tandem_repeats.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>

namespace seqtopo::significance {

std::vector<std::size_t> tandem_repeat_frames(const SimilarityMatrix& s, const TandemRepeatConfig& c) {
  if (s.rows != s.cols) throw std::invalid_argument("the enhanced scores must be square");
  return tandem_repeat_frames(align::ScoreSource::dense(std::span<const float>(s.values), s.rows, s.cols), c);
}

std::vector<std::size_t> tandem_repeat_frames(const align::ScoreSource& source, const TandemRepeatConfig& c) {
  if (source.rows() != source.cols()) throw std::invalid_argument("the enhanced scores must be square");
  if (c.near >= c.reach) throw std::invalid_argument("near must be below reach");
  if (!(c.level > 0) || !std::isfinite(c.level)) throw std::invalid_argument("level must be a finite number > 0");
  const std::size_t n = source.rows();
  // The band s(k, k + d), 1 <= d <= reach, of the rows frame i reads (k - reach - half_window ... k + half_window),
  // in a ring of rows: the scores are symmetric, so (k - d, k) is row k - d's cell d.
  const std::size_t ring = c.reach + 2 * c.half_window + 1;
  std::vector<float> band(ring * c.reach, 0.0F);
  std::size_t loaded = 0;  // rows [0, loaded) read
  const auto at = [&](std::size_t k, std::size_t d) { return band[(k % ring) * c.reach + d - 1]; };
  std::vector<bool> repeat(n, false);
  std::vector<double> diagonal(c.reach + 2, 0.0);
  // The sums along each diagonal d of the pairs (k, k + d) ahead of frame i and (k - d, k) behind it, k within
  // `half_window` frames of i: running sums as i moves (the pair leaving, the pair entering), summed afresh every
  // kRestart frames so rounding does not build up. O(reach) a frame, not O(reach x window).
  constexpr std::size_t kRestart = 64;
  const std::size_t h = c.half_window;
  std::vector<double> sum_ahead(c.reach + 1, 0.0), sum_behind(c.reach + 1, 0.0);
  std::vector<std::size_t> count_ahead(c.reach + 1, 0), count_behind(c.reach + 1, 0);
  const auto add = [&](std::size_t k, bool entering) {  // frame k's pairs into the window's sums, or out
    for (std::size_t d = c.near + 1; d <= c.reach; ++d) {
      if (k + d < n) {
        sum_ahead[d] += entering ? at(k, d) : -at(k, d);
        count_ahead[d] = entering ? count_ahead[d] + 1 : count_ahead[d] - 1;
      }
      if (k >= d) {
        sum_behind[d] += entering ? at(k - d, d) : -at(k - d, d);
        count_behind[d] = entering ? count_behind[d] + 1 : count_behind[d] - 1;
      }
    }
  };
  for (std::size_t i = 0; i < n; ++i) {
    const bool afresh = i % kRestart == 0;
    // The pair leaving the window, before its row leaves the ring.
    if (!afresh && i > h) add(i - h - 1, false);
    for (const std::size_t last = std::min(n - 1, i + h); loaded <= last; ++loaded) {
      if (loaded + 1 < n)
        source.read_row(loaded, loaded + 1, std::min(n, loaded + c.reach + 1), &band[(loaded % ring) * c.reach]);
    }
    const std::size_t lo = i > h ? i - h : 0, hi = std::min(n - 1, i + h);
    if (afresh) {
      std::fill(sum_ahead.begin(), sum_ahead.end(), 0.0);
      std::fill(sum_behind.begin(), sum_behind.end(), 0.0);
      std::fill(count_ahead.begin(), count_ahead.end(), 0);
      std::fill(count_behind.begin(), count_behind.end(), 0);
      for (std::size_t k = lo; k <= hi; ++k) add(k, true);
    } else if (i + h <= n - 1) {
      add(i + h, true);  // the pair entering
    }
    for (const bool ahead : {true, false}) {
      // The mean enhanced score along each diagonal d within the `half_window` frames around i, ahead of it or
      // behind it (a frame near a repeat's end sees its period on one side).
      for (std::size_t d = c.near + 1; d <= c.reach; ++d) {
        const std::size_t count = ahead ? count_ahead[d] : count_behind[d];
        diagonal[d] = count == 0 ? 0.0 : (ahead ? sum_ahead[d] : sum_behind[d]) / static_cast<double>(count);
      }
      // The centres of the runs of diagonals above the level, but for a run next to the `near` ones (the sequence's
      // own smoothness, or a stop, continued).
      std::vector<double> centres;
      std::size_t run_begin = 0;
      bool in_run = false;
      for (std::size_t d = c.near + 1; d <= c.reach + 1; ++d) {
        const bool alike = d <= c.reach && diagonal[d] > c.level;
        if (alike && !in_run) run_begin = d;
        if (!alike && in_run && run_begin > c.near + 1) centres.push_back(0.5 * static_cast<double>(run_begin + d - 1));
        in_run = alike;
      }
      // One period and two: runs at p and 2p (within a frame and a half).
      for (std::size_t a = 0; a < centres.size() && !repeat[i]; ++a) {
        for (std::size_t b = a + 1; b < centres.size(); ++b) {
          if (std::abs(centres[b] - 2 * centres[a]) <= 1.5) repeat[i] = true;
        }
      }
    }
  }
  // A repeat's frames each show its period only where the noise lets them: the frames between two flagged ones at
  // most `reach` apart are in the repeat too (a closing).
  std::size_t last = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (!repeat[i]) continue;
    if (last != n && i - last <= c.reach) {
      std::fill(repeat.begin() + static_cast<std::ptrdiff_t>(last), repeat.begin() + static_cast<std::ptrdiff_t>(i),
                true);
    }
    last = i;
  }
  // Stretches shorter than min_frames are left alone.
  std::vector<std::size_t> frames;
  for (std::size_t i = 0; i < n;) {
    std::size_t end = i;
    while (end < n && repeat[end]) ++end;
    if (end - i >= c.min_frames) {
      for (std::size_t k = i; k < end; ++k) frames.push_back(k);
    }
    i = end == i ? i + 1 : end;
  }
  return frames;
}

}  // namespace seqtopo::significance
