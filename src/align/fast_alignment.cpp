// The fast engine (fast_alignment.hpp, docs/engine.md): the scalar engine's algorithm and choice rules
// (smith_waterman.cpp) on int16 rows, in memory linear in the input.
//
// State of a pass: H rows every kCheckpointRows rows (checkpoints), each row's maximum, and the used
// pairs as per-row column lists (a used pair's score is replaced by kForbidden when its row is
// computed). Every other row is recomputed from the checkpoint above it when needed:
//  * the next end: the first row holding the largest row maximum, recomputed to find its first column;
//  * a capped plateau's far end: rows streamed downwards from the end while tight steps continue;
//  * the traceback: a window of rows above the end and columns left of it, recomputed and kept, widened
//    (doubled) until the alignment's start lies inside, then the scalar engine's rules on it;
//  * after an alignment: rows recomputed from the checkpoint above its first pair, updating the row
//    maxima and checkpoints, until a checkpoint below its last pair comes out unchanged (every later
//    row is then unchanged too).
#include "seqtopo/align/fast_alignment.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>

#include "fast_kernels.hpp"
#include "seqtopo/align/smith_waterman.hpp"
#include "plateau.hpp"
#include "search_region.hpp"
#include "step_box.hpp"

namespace seqtopo::align {

using detail::kForbidden;
using detail::kMaxStep;
using detail::kRowPadding;
using detail::quantize_one;
using detail::RowJob;
using Step = std::int16_t;

std::string_view to_string(Isa isa) {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse41: return "sse4.1";
    case Isa::avx2: return "avx2";
    case Isa::best: return "best";
  }
  return "?";
}

Isa best_isa() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) return Isa::avx2;
  if (__builtin_cpu_supports("sse4.1")) return Isa::sse41;
#endif
  return Isa::scalar;
}

namespace {

// Rows between checkpoints: 2 / 32 bytes per cell of memory; every recomputation starts at most this far above.
constexpr std::size_t kCheckpointRows = 32;

struct Kernels {
  detail::RowKernel row;
  detail::Quantizer quantize;
};

Kernels kernels_for(Isa wanted) {
  const Isa have = best_isa();
  // An ISA the CPU lacks falls back to the best one it has (the order of the enum is the order of power).
  const Isa isa = wanted == Isa::best || static_cast<int>(wanted) > static_cast<int>(have) ? have : wanted;
  switch (isa) {
    case Isa::avx2: return {detail::row_avx2, detail::quantize_avx2};
    case Isa::sse41: return {detail::row_sse41, detail::quantize_sse41};
    default: return {detail::row_scalar, detail::quantize_scalar};
  }
}

void validate(std::size_t rows, std::size_t cols, const AlignConfig& config) {
  auto bad = [](Score v) { return std::isnan(v) || v < 0; };
  if (bad(config.gap_a) || bad(config.gap_b)) throw std::invalid_argument("gap penalties must be >= 0");
  if (config.cap && (std::isnan(*config.cap) || *config.cap <= 0)) throw std::invalid_argument("cap must be > 0");
  if (std::isnan(config.threshold)) throw std::invalid_argument("threshold must be a number");
  if (config.self && rows != cols) {
    throw std::invalid_argument("self alignment needs a square score matrix, got " + std::to_string(rows) + " x " +
                                std::to_string(cols));
  }
  if (config.self && config.min_separation == 0) throw std::invalid_argument("min_separation must be >= 1");
}

bool whole(float v) { return std::nearbyint(v) == v; }

float largest_power_of_two_at_most(double limit) {
  float s = 1.0F;
  while (static_cast<double>(s) * 2 <= limit) s *= 2;
  while (static_cast<double>(s) > limit && s > 0x1p-60F) s /= 2;
  return s;
}

// Threshold in steps, clamped so it still compares right with any int16 value (32768 = unreachable).
int threshold_steps(float threshold, float scale) {
  const double t = std::nearbyint(static_cast<double>(threshold) * scale);
  return static_cast<int>(std::clamp(t, -32768.0, 32768.0));
}

// Gaps, cap and threshold of one pass in steps.
struct Steps {
  Step gap_a = 0, gap_b = 0, cap = kMaxStep;
  bool capped = false;
  int floor = 1;  // smallest reportable end value
  float scale = 1;
};

Steps steps_for(const AlignConfig& config, float scale) {
  Steps st;
  st.scale = scale;
  st.gap_a = quantize_one(config.gap_a, scale);
  st.gap_b = quantize_one(config.gap_b, scale);
  if (config.cap) {
    const double cap = std::nearbyint(static_cast<double>(*config.cap) * scale);
    if (cap > kMaxStep) {
      throw std::invalid_argument("cap " + std::to_string(*config.cap) + " at scale " + std::to_string(scale) +
                                  " exceeds the int16 range (32767 steps): use a smaller scale");
    }
    if (cap < 1) {
      throw std::invalid_argument("cap " + std::to_string(*config.cap) + " at scale " + std::to_string(scale) +
                                  " rounds to 0 steps: use a larger scale");
    }
    st.cap = static_cast<Step>(cap);
    st.capped = true;
  }
  st.floor = std::max(1, threshold_steps(config.threshold, scale));
  return st;
}

// Integer scores of pass rows.
class RowScores {
 public:
  virtual ~RowScores() = default;
  // Scores of pass row i (1-based) at pass columns [lo, hi]: p[j] for j in [lo, hi]. May fill and
  // return `steps` (a row buffer); `floats` has room for a row of the source.
  virtual const Step* row(std::size_t i, std::size_t lo, std::size_t hi, Step* steps, float* floats) const = 0;
};

class SourceRows final : public RowScores {
 public:
  SourceRows(const ScoreSource& source, Direction direction, float scale, detail::Quantizer quantize)
      : source_(source), reverse_(direction == Direction::reverse), scale_(scale), quantize_(quantize) {}
  const Step* row(std::size_t i, std::size_t lo, std::size_t hi, Step* steps, float* floats) const override {
    const std::size_t n = source_.cols(), count = hi - lo + 1;
    if (!reverse_) {
      source_.read_row(i - 1, lo - 1, hi, floats);
      quantize_(floats, count, scale_, steps + lo);
    } else {
      // pass columns lo..hi are source columns n-hi .. n-lo, in the opposite order
      source_.read_row(i - 1, n - hi, n - lo + 1, floats);
      quantize_(floats, count, scale_, steps + lo);
      std::reverse(steps + lo, steps + hi + 1);
    }
    return steps;
  }

 private:
  const ScoreSource& source_;
  bool reverse_;
  float scale_;
  detail::Quantizer quantize_;
};

// One precomputed row per letter of A's alphabet (a query profile over B, in pass column order).
class LetterRows final : public RowScores {
 public:
  LetterRows(const LetterScores& letters, Direction direction, float scale)
      : a_(letters.a), stride_(letters.b.size() + 1 + kRowPadding) {
    const std::size_t n = letters.b.size(), k = letters.alphabet;
    profile_.assign(k * stride_, 0);
    for (std::size_t x = 0; x < k; ++x) {
      for (std::size_t j = 1; j <= n; ++j) {
        const std::size_t col = direction == Direction::forward ? j - 1 : n - j;
        profile_[x * stride_ + j] = quantize_one(letters.matrix[x * k + letters.b[col]], scale);
      }
    }
  }
  const Step* row(std::size_t i, std::size_t, std::size_t, Step*, float*) const override {
    return profile_.data() + a_[i - 1] * stride_;
  }

 private:
  std::span<const std::uint8_t> a_;
  std::size_t stride_;
  std::vector<Step> profile_;
};

void validate_letters(const LetterScores& s) {
  if (s.matrix.size() != s.alphabet * s.alphabet) {
    throw std::invalid_argument("substitution matrix has " + std::to_string(s.matrix.size()) + " values, expected " +
                                std::to_string(s.alphabet) + " x " + std::to_string(s.alphabet));
  }
  auto check = [&](std::span<const std::uint8_t> seq, const char* name) {
    for (std::uint8_t c : seq) {
      if (c >= s.alphabet) {
        throw std::invalid_argument(std::string("sequence ") + name + " has letter " + std::to_string(c) +
                                    " outside an alphabet of " + std::to_string(s.alphabet));
      }
    }
  };
  check(s.a, "a");
  check(s.b, "b");
}

using Cell = std::pair<std::size_t, std::size_t>;  // (i, j) in pass coordinates, 1-based

// Buffers of one worker: a row of steps (scores) and a row of source floats.
struct Scratch {
  std::vector<Step> steps;
  std::vector<float> floats;
  explicit Scratch(std::size_t n) : steps(n + 1 + kRowPadding, 0), floats(n + kRowPadding, 0.0F) {}
};

// One pass of the fast engine.
class FastPass {
 public:
  FastPass(const RowScores& scores, std::size_t m, std::size_t n, const AlignConfig& config, const Steps& steps,
           const Kernels& kernels, unsigned threads)
      : scores_(scores), config_(config), st_(steps), kernel_(kernels.row), m_(m), n_(n), stride_(n + 1 + kRowPadding),
        threads_(std::max(1U, threads)) {}

  // The score-only fill: the largest cell value.
  Step best_value() { return fill(false); }

  std::vector<LocalAlignment> run() {
    fill(true);
    std::vector<LocalAlignment> out;
    while (out.size() < config_.max_alignments) {
      std::size_t bi = 0;
      for (std::size_t i = 1; i <= m_; ++i) {
        if (row_max_[i] > 0 && (bi == 0 || row_max_[i] > row_max_[bi])) bi = i;  // first maximal row
      }
      if (bi == 0 || row_max_[bi] < st_.floor) break;
      Cursor cursor(*this);
      cursor.seek(bi);
      const Step top = row_max_[bi];
      std::size_t bj = 1;
      while (cursor.h[bj] != top) ++bj;
      // A maximum at the cap is a plateau: take it whole. Otherwise the first maximum, as SIM does.
      const Cell end = st_.capped && top == st_.cap ? far_end(cursor, {bi, bj}) : Cell{bi, bj};
      out.push_back(recover(end));
      forbid_and_update(out.back());
    }
    return out;
  }

 private:
  // Columns [lo, hi] (1-based, inclusive) that row i may use (lo > hi: none).
  std::pair<std::size_t, std::size_t> region(std::size_t i) const { return detail::search_region(config_, n_, i); }


  // Scores of row i over [lo, hi] with the used pairs forbidden.
  const Step* row_scores(std::size_t i, std::size_t lo, std::size_t hi, Scratch& scratch) const {
    const Step* s = scores_.row(i, lo, hi, scratch.steps.data(), scratch.floats.data());
    if (forbidden_.empty() || forbidden_[i].empty()) return s;
    const auto& cols = forbidden_[i];
    auto first = std::lower_bound(cols.begin(), cols.end(), lo);
    if (first == cols.end() || *first > hi) return s;
    Step* out = scratch.steps.data();
    if (s != out) std::copy(s + lo, s + hi + 1, out + lo);
    for (auto it = first; it != cols.end() && *it <= hi; ++it) out[*it] = kForbidden;
    return out;
  }

  // Computes row i's columns [lo, hi] ∩ region into cur; zeroes the rest of [lo, hi]. Returns
  // (row max over those columns, score row pointer).
  std::pair<Step, const Step*> compute(std::size_t i, const Step* prev, Step* cur, std::size_t lo, std::size_t hi,
                                       Scratch& scratch) const {
    const auto [rlo, rhi] = region(i);
    const std::size_t a = std::max(lo, rlo), b = std::min(hi, rhi);
    if (a > b) {
      std::fill(cur + lo, cur + hi + 1, Step{0});
      return {0, scratch.steps.data()};
    }
    if (a > lo) std::fill(cur + lo, cur + a, Step{0});
    if (b < hi) std::fill(cur + b + 1, cur + hi + 1, Step{0});
    const Step* s = row_scores(i, a, b, scratch);
    RowJob job{prev, cur, s, a, b, st_.gap_a, st_.gap_b, st_.cap, cur[a - 1]};
    const Step best = kernel_(job);
    if (!st_.capped && best >= kMaxStep) {
      throw std::invalid_argument("cumulative score reaches the int16 range (32767 steps) at scale " +
                                  std::to_string(st_.scale) + ": set a cap or a smaller scale");
    }
    return {best, s};
  }

  // Fills every row, by column strips on threads_ threads in a wavefront (a strip's row i needs the
  // strip on its left to have finished row i). Keeps row maxima and checkpoints if asked.
  Step fill(bool keep) {
    if (keep) {
      row_max_.assign(m_ + 1, 0);
      checkpoints_.assign((m_ / kCheckpointRows + 1) * stride_, 0);
    }
    // Strips of at least 512 columns, so a strip's row costs far more than its synchronisation.
    const std::size_t strips = std::max<std::size_t>(1, std::min<std::size_t>(threads_, n_ / 512));
    constexpr std::size_t kRing = 64;  // rows kept; a strip may run this far ahead of the next one
    const std::size_t ring = strips == 1 ? 2 : kRing;
    std::vector<Step> rows(ring * stride_, 0);
    std::vector<std::vector<Step>> strip_max(strips, std::vector<Step>(keep ? m_ + 1 : 0, 0));
    std::vector<Step> best(strips, 0);
    std::vector<std::atomic<std::size_t>> done(strips);
    for (auto& d : done) d.store(0);
    std::atomic<bool> failed{false};
    std::vector<std::exception_ptr> errors(strips);

    auto work = [&](std::size_t k) {
      try {
        const std::size_t lo = 1 + n_ * k / strips, hi = n_ * (k + 1) / strips;
        Scratch scratch(n_);
        for (std::size_t i = 1; i <= m_; ++i) {
          if (k > 0) wait_for(done[k - 1], i, failed);
          if (k + 1 < strips && i > ring - 1) wait_for(done[k + 1], i - (ring - 1), failed);
          if (failed.load(std::memory_order_relaxed)) return;
          const Step* prev = rows.data() + ((i - 1) % ring) * stride_;
          Step* cur = rows.data() + (i % ring) * stride_;
          const Step v = compute(i, prev, cur, lo, hi, scratch).first;
          best[k] = std::max(best[k], v);
          if (keep) {
            strip_max[k][i] = v;
            if (i % kCheckpointRows == 0) {
              std::copy(cur + lo, cur + hi + 1, checkpoints_.data() + (i / kCheckpointRows) * stride_ + lo);
            }
          }
          if (strips > 1) {  // nobody waits on a single strip
            done[k].store(i, std::memory_order_release);
            done[k].notify_all();
          }
        }
      } catch (...) {
        errors[k] = std::current_exception();
        failed.store(true);
        for (auto& d : done) {
          d.store(m_ + 1);  // release every waiter
          d.notify_all();
        }
      }
    };
    std::vector<std::thread> pool;
    for (std::size_t k = 1; k < strips; ++k) pool.emplace_back(work, k);
    work(0);
    for (auto& t : pool) t.join();
    for (auto& e : errors) {
      if (e) std::rethrow_exception(e);
    }
    if (keep) {
      for (std::size_t i = 1; i <= m_; ++i) {
        for (std::size_t k = 0; k < strips; ++k) row_max_[i] = std::max(row_max_[i], strip_max[k][i]);
      }
    }
    return *std::max_element(best.begin(), best.end());
  }

  static void wait_for(const std::atomic<std::size_t>& counter, std::size_t value, const std::atomic<bool>& failed) {
    for (int spin = 0; spin < 2000; ++spin) {
      if (counter.load(std::memory_order_acquire) >= value) return;
    }
    for (std::size_t seen = counter.load(std::memory_order_acquire); seen < value && !failed.load();
         seen = counter.load(std::memory_order_acquire)) {
      counter.wait(seen, std::memory_order_acquire);
    }
  }

  // Rows recomputed one after another from a checkpoint: h is the current row, above the one before,
  // s the current row's scores (with used pairs forbidden).
  struct Cursor {
    const FastPass& pass;
    std::vector<Step> a, b;
    Step* above;
    Step* h;
    const Step* s = nullptr;
    std::size_t row = 0;
    Step max = 0;
    Scratch scratch;
    explicit Cursor(const FastPass& p)
        : pass(p), a(p.stride_, 0), b(p.stride_, 0), above(a.data()), h(b.data()), scratch(p.n_), last_col(p.n_) {}
    // Positions on checkpoint k (row k * kCheckpointRows).
    void start(std::size_t k) {
      const Step* c = pass.checkpoints_.data() + k * pass.stride_;
      std::copy(c, c + pass.stride_, h);
      row = k * kCheckpointRows;
      s = nullptr;
    }
    std::size_t last_col;  // columns computed: 1 .. last_col
    void advance() {
      std::swap(above, h);
      ++row;
      std::tie(max, s) = pass.compute(row, above, h, 1, last_col, scratch);
    }
    // Row i (>= 1), from the checkpoint strictly above it.
    void seek(std::size_t i) {
      start((i - 1) / kCheckpointRows);
      while (row < i) advance();
    }
  };

  // Tight steps (those attaining the cell's positive value) on rows held in memory: the scalar engine's
  // expressions in saturating int16, which equal them on these integer-valued inputs.
  int clamp(int v) const { return std::min(v, static_cast<int>(st_.cap)); }
  bool tight_diag(const Step* above, const Step* h, const Step* s, std::size_t j) const {
    return h[j] > 0 && clamp(detail::saturate(above[j - 1] + s[j])) == h[j];
  }
  bool tight_down(const Step* above, const Step* h, std::size_t j) const {
    return h[j] > 0 && clamp(detail::saturate(above[j] - st_.gap_a)) == h[j];
  }
  bool tight_right(const Step* h, std::size_t j) const {
    return h[j] > 0 && clamp(detail::saturate(h[j - 1] - st_.gap_b)) == h[j];
  }

  // The last maximal cell (row-major) reachable from `first` by tight steps, rows streamed downwards.
  Cell far_end(Cursor& c, Cell first) const {
    // Rows are streamed: c holds row i (h) and, after next_row, row i+1 with the row above it.
    struct Grid {
      const FastPass& p;
      Cursor& c;
      Step top_value;
      bool top(std::size_t, std::size_t j) const { return c.h[j] == top_value; }
      bool right(std::size_t, std::size_t j) const { return p.tight_right(c.h, j); }
      void next_row() const { c.advance(); }
      bool down(std::size_t, std::size_t j) const { return p.tight_down(c.above, c.h, j); }
      bool diag(std::size_t, std::size_t j) const { return p.tight_diag(c.above, c.h, c.s, j); }
    };
    return detail::plateau_far_end(first, m_, n_, Grid{*this, c, c.h[first.second]});
  }

  // Rows r0 .. r1 and columns c0 .. c1 of the table (and the scores from r0 + 1, c0 + 1), recomputed.
  // A question about a cell outside sets `outside` (the window is then too small) and answers 0/false.
  struct Window {
    std::size_t r0 = 0, r1 = 0, c0 = 0, c1 = 0, width = 0;
    std::vector<Step> h, s;
    Step cap = kMaxStep, gap_a = 0, gap_b = 0;
    mutable bool outside = false;
    Step value(std::size_t i, std::size_t j) const {
      if (i < r0 || j < c0) {
        outside = true;
        return 0;
      }
      return h[(i - r0) * width + (j - c0)];
    }
    Step score(std::size_t i, std::size_t j) const { return s[(i - r0) * width + (j - c0)]; }
    bool inner(std::size_t i, std::size_t j) const {
      if (i > r0 && j > c0) return true;
      outside = true;
      return false;
    }
    int clamp(int v) const { return std::min(v, static_cast<int>(cap)); }
    bool tight_diag(std::size_t i, std::size_t j) const {
      return inner(i, j) && value(i, j) > 0 && clamp(detail::saturate(value(i - 1, j - 1) + score(i, j))) == value(i, j);
    }
    bool tight_down(std::size_t i, std::size_t j) const {
      return inner(i, j) && value(i, j) > 0 && clamp(detail::saturate(value(i - 1, j) - gap_a)) == value(i, j);
    }
    bool tight_right(std::size_t i, std::size_t j) const {
      return inner(i, j) && value(i, j) > 0 && clamp(detail::saturate(value(i, j - 1) - gap_b)) == value(i, j);
    }
  };

  Window window(Cell end, std::size_t rows_above, std::size_t cols_left) const {
    Window w;
    w.cap = st_.cap;
    w.gap_a = st_.gap_a;
    w.gap_b = st_.gap_b;
    const std::size_t top = end.first > rows_above ? end.first - rows_above : 0;
    const std::size_t k = top / kCheckpointRows;
    w.r0 = k * kCheckpointRows;
    w.r1 = end.first;
    w.c0 = end.second > cols_left ? end.second - cols_left : 0;
    w.c1 = end.second;
    w.width = w.c1 - w.c0 + 1;
    w.h.assign((w.r1 - w.r0 + 1) * w.width, 0);
    w.s.assign(w.h.size(), 0);
    Cursor c(*this);
    c.last_col = w.c1;  // nothing right of the end can be on its path
    c.start(k);
    std::copy(c.h + w.c0, c.h + w.c1 + 1, w.h.begin());
    while (c.row < w.r1) {
      c.advance();
      const std::size_t r = c.row - w.r0;
      std::copy(c.h + w.c0, c.h + w.c1 + 1, w.h.begin() + static_cast<std::ptrdiff_t>(r * w.width));
      // scores are meaningful only where the region is (elsewhere h = 0 and they are never asked)
      const auto [lo, hi] = region(c.row);
      for (std::size_t j = std::max(w.c0, lo); j <= std::min(w.c1, hi); ++j) w.s[r * w.width + (j - w.c0)] = c.s[j];
    }
    return w;
  }

  // The latest start of an optimal alignment ending at `end` (the scalar engine's start_of on a window).
  static Cell latest_start(const Window& w, Cell end, std::vector<std::pair<std::size_t, std::size_t>>& spans) {
    spans.clear();
    std::vector<std::size_t> seeds{end.second}, closed;
    for (std::size_t i = end.first; i > 0 && !w.outside; --i) {
      std::sort(seeds.begin(), seeds.end(), std::greater<>());
      seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
      closed.clear();
      for (std::size_t j : seeds) {
        if (!closed.empty() && j >= closed.back()) continue;
        closed.push_back(j);
        while (j > 1 && w.tight_right(i, j)) closed.push_back(--j);
      }
      spans.emplace_back(closed.back(), closed.front());
      seeds.clear();
      std::size_t start_col = 0;
      bool found = false;
      for (std::size_t j : closed) {
        if (w.tight_diag(i, j)) {
          if (w.value(i - 1, j - 1) == 0) {
            if (!found || j - 1 > start_col) start_col = j - 1;
            found = true;
          } else {
            seeds.push_back(j - 1);
          }
        }
        if (w.tight_down(i, j)) seeds.push_back(j);
      }
      if (found && !w.outside) return {i - 1, start_col};
    }
    if (w.outside) return {0, 0};
    throw std::logic_error("alignment has no start");
  }

  // Step bits of the rectangle between start and end, as in the scalar engine: 1 diagonal, 2 down,
  // 4 right; row r keeps only columns lo[r] .. hi[r] (box coordinates), everything else reads 0.
  LocalAlignment recover(Cell end) const {
    std::vector<std::pair<std::size_t, std::size_t>> spans;
    std::size_t reach = kCheckpointRows;
    Window w;
    Cell start;
    for (;;) {
      w = window(end, reach, reach);
      start = latest_start(w, end, spans);
      if (!w.outside) break;
      reach *= 2;  // the start lies above or left of the window: widen it
    }
    detail::StepBox box;
    box.layout(start, spans, end.first - start.first + 1);
    const std::size_t rows = box.lo.size();
    for (std::size_t r = 1; r < rows; ++r) {
      const std::size_t i = start.first + r;
      for (std::size_t c = box.lo[r]; c <= box.hi[r]; ++c) {
        const std::size_t j = start.second + c;
        if (w.value(i, j) <= 0) continue;
        std::uint8_t bits = 0;
        if (w.tight_diag(i, j)) bits |= 1U;
        if (w.tight_down(i, j)) bits |= 2U;
        if (w.tight_right(i, j)) bits |= 4U;
        box.steps[box.index(r, c)] = bits;
      }
    }
    return detail::alignment_through(box, end, config_.direction, n_,
                                     static_cast<Score>(w.value(end.first, end.second)) / st_.scale);
  }

  // Forbids the alignment's pairs, then recomputes rows from the checkpoint above its first pair until
  // a checkpoint at or below its last pair is unchanged.
  void forbid_and_update(const LocalAlignment& a) {
    if (forbidden_.empty()) forbidden_.resize(m_ + 1);
    for (auto [r, c] : a.pairs) {
      const std::size_t i = r + 1, j = config_.direction == Direction::forward ? c + 1 : n_ - c;
      auto& cols = forbidden_[i];
      cols.insert(std::lower_bound(cols.begin(), cols.end(), j), j);
    }
    const std::size_t first_row = a.pairs.front().first + 1, last_row = a.pairs.back().first + 1;
    Cursor c(*this);
    c.start((first_row - 1) / kCheckpointRows);
    while (c.row < m_) {
      c.advance();
      row_max_[c.row] = c.max;
      if (c.row % kCheckpointRows != 0) continue;
      Step* stored = checkpoints_.data() + (c.row / kCheckpointRows) * stride_;
      if (c.row >= last_row && std::equal(c.h, c.h + n_ + 1, stored)) break;
      std::copy(c.h, c.h + n_ + 1, stored);
    }
  }

  const RowScores& scores_;
  const AlignConfig& config_;
  Steps st_;
  detail::RowKernel kernel_;
  std::size_t m_, n_, stride_;
  unsigned threads_;
  std::vector<Step> checkpoints_;   // row k * kCheckpointRows at k * stride_
  std::vector<Step> row_max_;       // each row's maximum
  std::vector<std::vector<std::size_t>> forbidden_;  // per row, sorted pass columns of used pairs
};

unsigned resolve(unsigned threads) {
  return threads != 0 ? threads : std::max(1U, std::thread::hardware_concurrency());
}

float checked_scale(const AlignConfig& config, const FastOptions& options) {
  const float scale = fast_scale(config, options);
  if (!std::isfinite(scale) || scale <= 0) throw std::invalid_argument("scale must be finite and > 0");
  return scale;
}

template <typename MakeRows>
std::vector<LocalAlignment> run_pass(std::size_t m, std::size_t n, const AlignConfig& config,
                                     const FastOptions& options, MakeRows make_rows) {
  validate(m, n, config);
  const float scale = checked_scale(config, options);
  const Steps steps = steps_for(config, scale);
  if (m == 0 || n == 0 || config.max_alignments == 0) return {};
  const Kernels kernels = kernels_for(options.isa);
  const auto rows = make_rows(scale, kernels);
  return FastPass(*rows, m, n, config, steps, kernels, resolve(options.threads)).run();
}

template <typename MakeRows>
Score best_pass(std::size_t m, std::size_t n, AlignConfig config, const FastOptions& options, MakeRows make_rows) {
  validate(m, n, config);
  const float scale = checked_scale(config, options);
  const Steps steps = steps_for(config, scale);
  if (m == 0 || n == 0) return 0;
  const Kernels kernels = kernels_for(options.isa);
  const auto rows = make_rows(scale, kernels);
  return static_cast<Score>(FastPass(*rows, m, n, config, steps, kernels, resolve(options.threads)).best_value()) /
         scale;
}

}  // namespace

float fast_scale(const AlignConfig& config, const FastOptions& options) {
  if (options.scale != 0) return options.scale;
  if (config.cap) {
    if (std::isnan(*config.cap) || *config.cap <= 0) throw std::invalid_argument("cap must be > 0");
    return largest_power_of_two_at_most(kMaxStep / static_cast<double>(*config.cap));
  }
  if (whole(config.gap_a) && whole(config.gap_b) && whole(config.threshold)) return 1.0F;
  const double largest = std::max({1.0, static_cast<double>(config.gap_a), static_cast<double>(config.gap_b),
                                   static_cast<double>(config.threshold)});
  return largest_power_of_two_at_most(255.0 / largest);
}

ScoreSource quantized(const ScoreSource& scores, float scale) {
  return ScoreSource(scores.rows(), scores.cols(),
                     [&scores, scale](std::size_t i, std::size_t j_begin, std::size_t j_end, Score* out) {
                       scores.read_row(i, j_begin, j_end, out);
                       for (std::size_t k = 0; k < j_end - j_begin; ++k) out[k] = quantize_one(out[k], scale);
                     });
}

AlignConfig quantized(const AlignConfig& config, float scale) {
  AlignConfig q = config;
  const Steps st = steps_for(config, scale);
  q.gap_a = st.gap_a;
  q.gap_b = st.gap_b;
  if (config.cap) q.cap = st.cap;
  q.threshold = static_cast<Score>(threshold_steps(config.threshold, scale));
  return q;
}

ScoreSource LetterScores::source() const {
  validate_letters(*this);
  return ScoreSource::function(a.size(), b.size(), [s = *this](std::size_t i, std::size_t j) {
    return s.matrix[s.a[i] * s.alphabet + s.b[j]];
  });
}

std::vector<LocalAlignment> fast_local_alignments(const ScoreSource& scores, const AlignConfig& config,
                                                  const FastOptions& options) {
  return run_pass(scores.rows(), scores.cols(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<SourceRows>(scores, config.direction, scale, k.quantize);
  });
}

std::vector<LocalAlignment> fast_local_alignments(const LetterScores& scores, const AlignConfig& config,
                                                  const FastOptions& options) {
  validate_letters(scores);
  return run_pass(scores.a.size(), scores.b.size(), config, options, [&](float scale, const Kernels&) {
    return std::make_unique<LetterRows>(scores, config.direction, scale);
  });
}

Score fast_best_score(const ScoreSource& scores, const AlignConfig& config, const FastOptions& options) {
  return best_pass(scores.rows(), scores.cols(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<SourceRows>(scores, config.direction, scale, k.quantize);
  });
}

Score fast_best_score(const LetterScores& scores, const AlignConfig& config, const FastOptions& options) {
  validate_letters(scores);
  return best_pass(scores.a.size(), scores.b.size(), config, options, [&](float scale, const Kernels&) {
    return std::make_unique<LetterRows>(scores, config.direction, scale);
  });
}

std::vector<LocalAlignment> fast_local_alignments_both(const ScoreSource& scores, AlignConfig config,
                                                       const FastOptions& options) {
  AlignConfig forward = config, reverse = config;
  forward.direction = Direction::forward;
  reverse.direction = Direction::reverse;
  const unsigned threads = resolve(options.threads);
  std::vector<LocalAlignment> fwd, rev;
  if (threads > 1) {
    // the two passes share the cores: each fills with half of them
    FastOptions half = options;
    half.threads = std::max(1U, threads / 2);
    auto rev_future = std::async(std::launch::async, [&] { return fast_local_alignments(scores, reverse, half); });
    fwd = fast_local_alignments(scores, forward, half);
    rev = rev_future.get();
  } else {
    fwd = fast_local_alignments(scores, forward, options);
    rev = fast_local_alignments(scores, reverse, options);
  }
  return merge_directions(std::move(fwd), std::move(rev), config.max_alignments);
}

}  // namespace seqtopo::align
