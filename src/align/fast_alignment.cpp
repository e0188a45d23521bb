// The fast engine (fast_alignment.hpp, docs/engine.md): the scalar engine's algorithm and choice rules
// (smith_waterman.cpp) on int16 rows, without a traceback table: 1/8 byte per cell instead of 5.
//
// State of a pass: H at the boundaries of kTile x kTile tiles (every kTile-th row and column), each
// tile's maximum, and the used pairs as per-row column lists (a used pair's score is replaced by
// kForbidden when its row is computed). Any piece of H is recomputed exactly from the boundaries
// around it, so every question costs the size of its answer, not the width of the table:
//  * the next end: the first band of tiles holding the largest maximum; its tiles at that maximum are
//    recomputed to find the first cell;
//  * a capped plateau's far end: rows streamed downwards from the end, over columns from the end's tile
//    to a width doubled while the plateau reaches it;
//  * the traceback: a window of rows above the end and columns left of it, recomputed and kept, widened
//    (doubled) until the alignment's start lies inside, then the scalar engine's rules on it;
//  * after an alignment: the tiles holding its pairs are recomputed, then every tile one of whose inputs
//    (top row, left column, corner) came out changed, band by band.
#include "seqtopo/align/fast_alignment.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>

#include "check_config.hpp"
#include "fast_kernels.hpp"
#include "plateau.hpp"
#include "search_region.hpp"
#include "seqtopo/align/smith_waterman.hpp"
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
    case Isa::scalar:
      return "scalar";
    case Isa::sse41:
      return "sse4.1";
    case Isa::avx2:
      return "avx2";
    case Isa::best:
      return "best";
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

// Side of the tiles whose boundaries the engine keeps: every 32nd row and every 32nd column of H, 2 x 2 / 32
// bytes per cell of memory; every recomputation starts at most this far above and left. The striped
// kernels' lanes are tiles.
constexpr std::size_t kTile = detail::kTileSide;

// The row kernel (every recomputation, and the scalar fill), the quantizer, and the fill's striped
// kernels (none for the scalar ISA, which fills row by row with the row kernel: the reference).
struct Kernels {
  detail::RowKernel row;
  detail::Quantizer quantize;
  detail::StripedKernel striped16 = nullptr, striped8 = nullptr;
  detail::BlockStriper16 stripe16 = nullptr;
  detail::BlockStriper8 stripe8 = nullptr;
  detail::BlockDestriper16 destripe16 = nullptr;
  detail::BlockDestriper8 destripe8 = nullptr;
  std::size_t lanes16 = 0, lanes8 = 0;
  // Columns of the striped fill's strips come in whole units: a block of either width (lanes8 = 2 lanes16).
  std::size_t unit() const { return kTile * lanes8; }
};

Kernels kernels_for(Isa wanted) {
  const Isa have = best_isa();
  // An ISA the CPU lacks falls back to the best one it has (the order of the enum is the order of power).
  const Isa isa = wanted == Isa::best || static_cast<int>(wanted) > static_cast<int>(have) ? have : wanted;
  Kernels k{detail::row_scalar, detail::quantize_scalar};
  if (isa == Isa::avx2) {
    k = {detail::row_avx2, detail::quantize_avx2, detail::striped16_avx2, detail::striped8_avx2};
    k.stripe16 = detail::stripe16_avx2;
    k.stripe8 = detail::stripe8_avx2;
    k.destripe16 = detail::destripe16_avx2;
    k.destripe8 = detail::destripe8_avx2;
    k.lanes16 = 16;
    k.lanes8 = 32;
  } else if (isa == Isa::sse41) {
    k = {detail::row_sse41, detail::quantize_sse41, detail::striped16_sse41, detail::striped8_sse41};
    k.stripe16 = detail::stripe16_sse41;
    k.stripe8 = detail::stripe8_sse41;
    k.destripe16 = detail::destripe16_sse41;
    k.destripe8 = detail::destripe8_sse41;
    k.lanes16 = 8;
    k.lanes8 = 16;
  }
  return k;
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

// Buffers of one worker: a row of steps (scores) and a row of source floats; for the striped fill, the
// scores of its strip in the striped layout.
struct Scratch {
  std::vector<Step> steps;
  std::vector<float> floats;
  std::vector<std::int16_t> striped16;
  std::vector<std::int8_t> striped8;
  explicit Scratch(std::size_t n) : steps(n + 1 + kRowPadding, 0), floats(n + kRowPadding, 0.0F) {}
};

std::int8_t saturate8(Step v) { return static_cast<std::int8_t>(std::clamp<int>(v, -128, 127)); }

// Whether every score fits in an int8 row.
bool fits_int8(const Step* p, std::size_t count) {
  Step lo = 0, hi = 0;
  for (std::size_t k = 0; k < count; ++k) {
    lo = std::min(lo, p[k]);
    hi = std::max(hi, p[k]);
  }
  return lo >= -128 && hi <= 127;
}

// Scores p[j] of pass columns j in [a, b] into the striped layout of a strip that starts at column lo:
// out[striped_index(j - lo, lanes)], saturated to int8 for an int8 row. Whole blocks go through the
// vector block striper if there is one, the ends of the range element by element.
template <typename T, typename BlockStriper>
void stripe(const Step* p, std::size_t lo, std::size_t a, std::size_t b, std::size_t lanes, T* out,
            BlockStriper block_striper) {
  const std::size_t block = kTile * lanes;
  if (block_striper) {
    const std::size_t first = (a - lo + block - 1) / block, end = (b - lo + 1) / block;  // whole blocks
    if (first < end) {
      for (std::size_t k = first; k < end; ++k) block_striper(p + lo + k * block, out + k * block);
      if (a < lo + first * block) stripe(p, lo, a, lo + first * block - 1, lanes, out, BlockStriper{});
      if (lo + end * block <= b) stripe(p, lo, lo + end * block, b, lanes, out, BlockStriper{});
      return;
    }
  }
  std::size_t rel = a - lo, base = rel - rel % block, lane = rel % block / kTile, seg = rel % kTile;
  for (std::size_t j = a; j <= b; ++j) {
    const Step v = p[j];
    if constexpr (sizeof(T) == 1) {
      out[base + seg * lanes + lane] = saturate8(v);
    } else {
      out[base + seg * lanes + lane] = v;
    }
    if (++seg == kTile) {
      seg = 0;
      if (++lane == lanes) {
        lane = 0;
        base += block;
      }
    }
  }
}

// Integer scores of pass rows.
class RowScores {
 public:
  virtual ~RowScores() = default;
  // Scores of pass row i (1-based) at pass columns [lo, hi]: p[j] for j in [lo, hi]. May fill and
  // return `steps` (a row buffer); `floats` has room for a row of the source.
  virtual const Step* row(std::size_t i, std::size_t lo, std::size_t hi, Step* steps, float* floats) const = 0;
  // The same scores over [a, b] for the striped fill, in the striped layout (int8 if `bytes`) of the strip
  // that starts at column lo (lo - 1 a multiple of Kernels::unit()); elements outside [a, b] unspecified,
  // <= 0 past the strip's end. May fill and return the scratch's striped buffer of that width (whole
  // blocks over the strip). For int8, nullptr if a score is outside [-128, 127].
  virtual const void* striped(std::size_t i, std::size_t lo, std::size_t a, std::size_t b, bool bytes,
                              Scratch& scratch) const = 0;
  // Whether striped() uses the scratch (a fill's strips allocate it only then).
  virtual bool uses_scratch() const { return true; }
  // Whether every score fits int8: int16 rows then read the int8 layout (StripedJob::score8).
  virtual bool int8_scores() const { return false; }
};

class SourceRows final : public RowScores {
 public:
  SourceRows(const ScoreSource& source, Direction direction, float scale, const Kernels& kernels)
      : source_(source),
        reverse_(direction == Direction::reverse),
        scale_(scale),
        quantize_(kernels.quantize),
        kernels_(kernels) {}
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
  const void* striped(std::size_t i, std::size_t lo, std::size_t a, std::size_t b, bool bytes,
                      Scratch& scratch) const override {
    const Step* p = row(i, a, b, scratch.steps.data(), scratch.floats.data());
    if (bytes && !fits_int8(p + a, b - a + 1)) return nullptr;
    if (bytes) {
      stripe(p, lo, a, b, kernels_.lanes8, scratch.striped8.data(), kernels_.stripe8);
      return scratch.striped8.data();
    }
    stripe(p, lo, a, b, kernels_.lanes16, scratch.striped16.data(), kernels_.stripe16);
    return scratch.striped16.data();
  }

 private:
  const ScoreSource& source_;
  bool reverse_;
  float scale_;
  detail::Quantizer quantize_;
  Kernels kernels_;
};

// One precomputed row per letter of A's alphabet (a query profile over B, in pass column order), and for
// the striped fill the same rows in the striped layouts of both widths (whole units over [1, n]). Each of
// the three is built on its first use: a fill needs only the int8 layout if the scores fit int8 (int16
// rows widen them as they load them), and the other two would be most of the memory a score-only fill
// touches (fresh pages, faulted in per call).
class LetterRows final : public RowScores {
 public:
  LetterRows(const LetterScores& letters, Direction direction, float scale, const Kernels& kernels)
      : a_(letters.a),
        b_(letters.b),
        reverse_(direction == Direction::reverse),
        letters_(letters.alphabet),
        stride_(letters.b.size() + 1 + kRowPadding),
        kernels_(kernels),
        matrix_(letters.alphabet * letters.alphabet) {
    // quantized once: the same steps as quantizing every cell's score
    for (std::size_t x = 0; x < matrix_.size(); ++x) matrix_[x] = quantize_one(letters.matrix[x], scale);
    if (kernels.striped16) {
      striped_stride_ = (b_.size() + kernels.unit() - 1) / kernels.unit() * kernels.unit();
      fits_int8_ = fits_int8(matrix_.data(), matrix_.size());
    }
  }
  const Step* row(std::size_t i, std::size_t, std::size_t, Step*, float*) const override {
    std::call_once(profile_once_, [this] {
      profile_.assign(letters_ * stride_, 0);
      for (std::size_t x = 0; x < letters_; ++x) natural_row(x, profile_.data() + x * stride_);
    });
    return profile_.data() + a_[i - 1] * stride_;
  }
  // Strips start at a block boundary of both layouts, so a strip's row is a piece of the whole row's.
  const void* striped(std::size_t i, std::size_t lo, std::size_t, std::size_t, bool bytes, Scratch&) const override {
    const std::size_t at = a_[i - 1] * striped_stride_ + (lo - 1);
    if (bytes) {
      if (!fits_int8_) return nullptr;
      std::call_once(striped8_once_, [this] { build_striped(kernels_.lanes8, striped8_, kernels_.stripe8); });
      return striped8_.data() + at;
    }
    std::call_once(striped16_once_, [this] { build_striped(kernels_.lanes16, striped16_, kernels_.stripe16); });
    return striped16_.data() + at;
  }
  bool uses_scratch() const override { return false; }
  bool int8_scores() const override { return fits_int8_; }

 private:
  // The scores of letter x against B in pass column order: out[j] for j in [1, n].
  void natural_row(std::size_t x, Step* out) const {
    const std::size_t n = b_.size();
    const Step* scores = matrix_.data() + x * letters_;
    for (std::size_t j = 1; j <= n; ++j) out[j] = scores[b_[reverse_ ? n - j : j - 1]];
  }
  // Every letter's row in one striped layout (padding past n: 0), through one natural row.
  template <typename T, typename BlockStriper>
  void build_striped(std::size_t lanes, std::vector<T>& out, BlockStriper block_striper) const {
    out.assign(letters_ * striped_stride_, 0);
    std::vector<Step> natural(stride_, 0);
    for (std::size_t x = 0; x < letters_; ++x) {
      natural_row(x, natural.data());
      stripe(natural.data(), 1, 1, b_.size(), lanes, out.data() + x * striped_stride_, block_striper);
    }
  }

  std::span<const std::uint8_t> a_, b_;
  bool reverse_;
  std::size_t letters_, stride_;
  Kernels kernels_;
  std::vector<Step> matrix_;
  std::size_t striped_stride_ = 0;
  bool fits_int8_ = false;
  mutable std::once_flag profile_once_, striped8_once_, striped16_once_;
  mutable std::vector<Step> profile_;
  mutable std::vector<std::int16_t> striped16_;
  mutable std::vector<std::int8_t> striped8_;
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

// One pass of the fast engine.
class FastPass {
 public:
  FastPass(const RowScores& scores, std::size_t m, std::size_t n, const AlignConfig& config, const Steps& steps,
           const Kernels& kernels, unsigned threads)
      : scores_(scores),
        config_(config),
        st_(steps),
        kernel_(kernels.row),
        kernels_(kernels),
        m_(m),
        n_(n),
        stride_(n + 1 + kRowPadding),
        bands_((m + kTile - 1) / kTile),
        tiles_((n + kTile - 1) / kTile),
        column_stride_(n / kTile + 1),
        threads_(std::max(1U, threads)) {}

  // The score-only fill: the largest cell value.
  Step best_value() { return fill(false); }

  std::vector<LocalAlignment> run() {
    fill(true);
    buffers_ = std::make_unique<Buffers>(n_, stride_);
    std::vector<LocalAlignment> out;
    while (out.size() < config_.max_alignments) {
      const auto top = std::max_element(band_max_.begin(), band_max_.end());  // the first maximal band
      if (top == band_max_.end() || *top < st_.floor) break;
      const Cell first = first_cell(static_cast<std::size_t>(top - band_max_.begin()), *top);
      // A maximum at the cap is a plateau: take it whole. Otherwise the first maximum, as SIM does.
      const Cell end = st_.capped && *top == st_.cap ? far_end(first) : first;
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

  // Computes row i's columns [lo, hi] ∩ region into cur (cur[lo - 1] holds H(i, lo - 1)); zeroes the
  // rest of [lo, hi]. Returns (row max over those columns, score row pointer).
  std::pair<Step, const Step*> compute(std::size_t i, const Step* prev, Step* cur, std::size_t lo, std::size_t hi,
                                       Scratch& scratch, Step* column_max = nullptr) const {
    const auto [rlo, rhi] = region(i);
    const std::size_t a = std::max(lo, rlo), b = std::min(hi, rhi);
    if (a > b) {
      std::fill(cur + lo, cur + hi + 1, Step{0});
      return {0, scratch.steps.data()};
    }
    if (a > lo) std::fill(cur + lo, cur + a, Step{0});
    if (b < hi) std::fill(cur + b + 1, cur + hi + 1, Step{0});
    const Step* s = row_scores(i, a, b, scratch);
    RowJob job{prev, cur, s, a, b, st_.gap_a, st_.gap_b, st_.cap, cur[a - 1], column_max};
    const Step best = kernel_(job);
    check_overflow(best);
    return {best, s};
  }

  // Fills every row, by column strips on threads_ threads in a wavefront (a strip's row i needs the strip
  // on its left to have finished row i). Keeps the tiles' boundaries and maxima if asked. The striped
  // kernels fill when the ISA has them; the scalar ISA fills row by row with the row kernel.
  Step fill(bool keep) {
    if (keep) {
      checkpoints_.assign((m_ / kTile + 1) * stride_, 0);
      columns_.assign((m_ + 1) * column_stride_, 0);
      tile_max_.assign(bands_ * tiles_, 0);
    }
    const Step best = kernels_.striped16 ? fill_striped(keep) : fill_rows(keep);
    if (keep) {
      band_max_.assign(bands_, 0);
      for (std::size_t b = 0; b < bands_; ++b) update_band_max(b);
    }
    return best;
  }

  static constexpr std::size_t kRing = 64;  // rows kept; a strip may run this far ahead of the next one

  // Runs strip(k) = make_strip(k) for k < strips, each on its own thread (strip 0 on this one), calling
  // strip(i) for rows i = 1 .. m in a wavefront: strip k's row i once strip k - 1 has finished row i,
  // and at most ring - 1 rows ahead of strip k + 1. Rethrows a strip's exception.
  template <typename MakeStrip>
  void wavefront(std::size_t strips, std::size_t ring, MakeStrip make_strip) const {
    std::vector<std::atomic<std::size_t>> done(strips);
    for (auto& d : done) d.store(0);
    std::atomic<bool> failed{false};
    std::vector<std::exception_ptr> errors(strips);
    auto work = [&](std::size_t k) {
      try {
        auto strip = make_strip(k);
        for (std::size_t i = 1; i <= m_; ++i) {
          if (k > 0) wait_for(done[k - 1], i, failed);
          if (k + 1 < strips && i > ring - 1) wait_for(done[k + 1], i - (ring - 1), failed);
          if (failed.load(std::memory_order_relaxed)) return;
          strip(i);
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
  }

  // The row-by-row fill: strips of whole tiles (at least 512 columns, so a strip's row costs far more
  // than its synchronisation) sharing a ring of natural rows.
  Step fill_rows(bool keep) {
    const std::size_t strips = std::max<std::size_t>(1, std::min<std::size_t>(threads_, n_ / 512));
    const std::size_t ring = strips == 1 ? 2 : kRing;
    std::vector<Step> rows(ring * stride_, 0);
    std::vector<Step> best(strips, 0);
    wavefront(strips, ring, [&](std::size_t k) {
      const std::size_t t0 = tiles_ * k / strips, t1 = tiles_ * (k + 1) / strips;
      const std::size_t lo = t0 * kTile + 1, hi = std::min(n_, t1 * kTile);
      return [this, &rows, &best, keep, ring, k, t0, t1, lo, hi, scratch = Scratch(n_),
              band = std::vector<Step>(keep ? stride_ : 0, 0)](std::size_t i) mutable {
        const Step* prev = rows.data() + ((i - 1) % ring) * stride_;
        Step* cur = rows.data() + (i % ring) * stride_;
        const Step v = compute(i, prev, cur, lo, hi, scratch, keep ? band.data() : nullptr).first;
        best[k] = std::max(best[k], v);
        if (keep) keep_row(i, cur, t0, t1, band.data());
      };
    });
    return *std::max_element(best.begin(), best.end());
  }

  // The striped fill: strips of whole units (Kernels::unit(): a block of either width), each with its own
  // two rows in the striped layout; strip k passes its last column to strip k + 1 through a ring. A strip
  // computes in int8 lanes (H - 128, fast_kernels.hpp) while that is exact: gaps <= 127, the row's scores
  // in [-128, 127], and the cap below 255 or else no row reaching 255; from the first row that breaks a
  // rule it goes on in int16, that row included. Every cell's value is the same for any strip count and
  // either width.
  Step fill_striped(bool keep) {
    const std::size_t unit = kernels_.unit(), units = (n_ + unit - 1) / unit;
    const std::size_t strips = std::max<std::size_t>(1, std::min({std::size_t{threads_}, units, n_ / 512}));
    const std::size_t ring = strips == 1 ? 2 : kRing;
    std::vector<Step> edges(strips * ring, 0);  // H(i, last column of strip k) at k * ring + i % ring
    std::vector<Step> best(strips, 0);
    wavefront(strips, ring, [&](std::size_t k) {
      const std::size_t lo = units * k / strips * unit + 1, hi = std::min(n_, units * (k + 1) / strips * unit);
      return StripedStrip(*this, keep, k, strips, lo, hi, edges.data(), ring, best[k]);
    });
    return *std::max_element(best.begin(), best.end());
  }

  // One strip of the striped fill; strip(i) computes row i.
  class StripedStrip {
   public:
    StripedStrip(FastPass& pass, bool keep, std::size_t k, std::size_t strips, std::size_t lo, std::size_t hi,
                 Step* edges, std::size_t ring, Step& best)
        : pass_(pass),
          keep_(keep),
          exact8_(pass.st_.capped && pass.st_.cap < detail::kInt8Limit),
          bytes_(pass.st_.gap_a <= detail::kInt8Gap && pass.st_.gap_b <= detail::kInt8Gap),
          k_(k),
          strips_(strips),
          lo_(lo),
          hi_(hi),
          width_(hi - lo + 1),
          padded_((width_ + pass.kernels_.unit() - 1) / pass.kernels_.unit() * pass.kernels_.unit()),
          ring_(ring),
          edges_(edges),
          best_(best),
          scratch_(pass.scores_.uses_scratch() ? pass.n_ : 0),
          rows8_(2 * padded_, static_cast<std::int8_t>(-detail::kInt8Offset)),  // H = 0
          tiles_(padded_ / kTile, 0) {
      if (bytes_) {
        if (pass.scores_.uses_scratch()) scratch_.striped8.assign(padded_, 0);
      } else {  // gaps beyond int8: int16 from the start
        rows16_.assign(2 * padded_, 0);
        if (pass.scores_.uses_scratch()) scratch_.striped16.assign(padded_, 0);
      }
    }

    void operator()(std::size_t i) {
      const FastPass& p = pass_;
      const auto [rlo, rhi] = p.region(i);
      const std::size_t a = std::max(lo_, rlo), b = std::min(hi_, rhi);
      const Step left = k_ > 0 ? edges_[(k_ - 1) * ring_ + i % ring_] : Step{0};
      const Step diag_left = k_ > 0 ? edges_[(k_ - 1) * ring_ + (i - 1) % ring_] : Step{0};
      // A row with no searched column here is 0 here, and so were the rows above (regions only grow).
      if (a <= b) {
        detail::StripedJob job{nullptr,
                               nullptr,
                               nullptr,
                               width_,
                               a - lo_,
                               b - lo_ + 1,
                               left,
                               diag_left,
                               p.st_.gap_a,
                               p.st_.gap_b,
                               p.st_.cap,
                               tiles_.data(),
                               keep_ ? pass_.columns_.data() + i * p.column_stride_ + (lo_ - 1) / kTile + 1 : nullptr,
                               &carry_};
        Step v = 0;
        if (bytes_ && !exact8_ && std::max(left, diag_left) >= detail::kInt8Limit) to_int16();
        if (bytes_) {
          job.score = p.scores_.striped(i, lo_, a, b, true, scratch_);
          if (!job.score) to_int16();  // a score outside int8
        }
        if (bytes_) {
          job.prev = rows8_.data() + prev_ * padded_;
          job.cur = rows8_.data() + (1 - prev_) * padded_;
          if (!exact8_) saved_tiles_ = tiles_;  // a row that may saturate leaves nothing that is kept
          v = p.kernels_.striped8(job);
          if (!exact8_ && v >= detail::kInt8Limit) {                              // redo the row in int16
            std::copy(saved_tiles_.begin(), saved_tiles_.end(), tiles_.begin());  // job.tile_max stays valid
            to_int16();
          }
        }
        if (!bytes_) {
          job.prev = rows16_.data() + prev_ * padded_;
          job.cur = rows16_.data() + (1 - prev_) * padded_;
          job.score8 = p.scores_.int8_scores();
          job.score = p.scores_.striped(i, lo_, a, b, job.score8, scratch_);
          v = p.kernels_.striped16(job);
          p.check_overflow(v);
        }
        best_ = std::max(best_, v);
      }
      prev_ = 1 - prev_;  // row i is now the previous row
      if (keep_ && i % kTile == 0) {
        Step* out = pass_.checkpoints_.data() + (i / kTile) * p.stride_ + lo_;
        destripe(out);
      }
      if (keep_ && (i % kTile == 0 || i == p.m_)) {
        const std::size_t count = (width_ + kTile - 1) / kTile;
        std::copy(
            tiles_.begin(), tiles_.begin() + static_cast<std::ptrdiff_t>(count),
            pass_.tile_max_.begin() + static_cast<std::ptrdiff_t>((i - 1) / kTile * p.tiles_ + (lo_ - 1) / kTile));
        std::fill(tiles_.begin(), tiles_.end(), Step{0});
      }
      if (k_ + 1 < strips_) edges_[k_ * ring_ + i % ring_] = value(width_ - 1);
    }

   private:
    // H of the previous row at strip column rel.
    Step value(std::size_t rel) const {
      const std::size_t at = prev_ * padded_;
      if (bytes_)
        return static_cast<Step>(rows8_[at + detail::striped_index(rel, pass_.kernels_.lanes8)] + detail::kInt8Offset);
      return rows16_[at + detail::striped_index(rel, pass_.kernels_.lanes16)];
    }

    // H of the previous row in natural order: out[rel] for rel < width_, block by block (the last one,
    // partial, through a buffer).
    void destripe(Step* out) const {
      const Kernels& k = pass_.kernels_;
      const std::size_t block = kTile * (bytes_ ? k.lanes8 : k.lanes16);
      std::vector<Step> tail;
      for (std::size_t b0 = 0; b0 < width_; b0 += block) {
        Step* to = out + b0;
        if (b0 + block > width_) {
          tail.resize(block);
          to = tail.data();
        }
        if (bytes_) {
          k.destripe8(rows8_.data() + prev_ * padded_ + b0, to);
        } else {
          k.destripe16(rows16_.data() + prev_ * padded_ + b0, to);
        }
        if (to != out + b0) std::copy(tail.begin(), tail.begin() + static_cast<std::ptrdiff_t>(width_ - b0), out + b0);
      }
    }

    // From int8 to int16 rows: the previous row (exact) is converted, the current one starts at 0.
    void to_int16() {
      rows16_.assign(2 * padded_, 0);
      std::vector<Step> natural(width_);
      destripe(natural.data());
      const std::size_t at = prev_ * padded_;
      for (std::size_t rel = 0; rel < width_; ++rel) {
        rows16_[at + detail::striped_index(rel, pass_.kernels_.lanes16)] = natural[rel];
      }
      if (pass_.scores_.uses_scratch()) scratch_.striped16.assign(padded_, 0);
      bytes_ = false;
    }

    FastPass& pass_;
    bool keep_, exact8_, bytes_;
    std::size_t k_, strips_, lo_, hi_, width_, padded_, ring_;
    Step* edges_;
    Step& best_;
    Scratch scratch_;
    std::size_t prev_ = 0;     // which of the two rows holds the previous row
    detail::CarryHint carry_;  // the kernels' hint (StripedJob)
    std::vector<std::int8_t> rows8_;
    std::vector<Step> rows16_;
    std::vector<Step> tiles_;        // the tiles' maxima over the band so far
    std::vector<Step> saved_tiles_;  // the same before an int8 row that may saturate
  };

  // Without a cap, a cell at 32767 steps may have saturated: a clear error, never a wrong alignment.
  void check_overflow(Step best) const {
    if (!st_.capped && best >= kMaxStep) {
      throw std::invalid_argument("cumulative score reaches the int16 range (32767 steps) at scale " +
                                  std::to_string(st_.scale) + ": set a cap or a smaller scale");
    }
  }

  // What the alignment phase keeps of row i, tiles t0 .. t1 - 1: the right column of every tile, the
  // row itself on a checkpoint row, and the tiles' maxima at the end of the band (from `band`, the
  // band's column maxima, which the kernel keeps).
  void keep_row(std::size_t i, const Step* cur, std::size_t t0, std::size_t t1, Step* band) {
    const std::size_t lo = t0 * kTile + 1, hi = std::min(n_, t1 * kTile);
    for (std::size_t q = t0 + 1; q <= t1 && q * kTile <= n_; ++q) columns_[i * column_stride_ + q] = cur[q * kTile];
    if (i % kTile == 0) std::copy(cur + lo, cur + hi + 1, checkpoints_.data() + (i / kTile) * stride_ + lo);
    if (i % kTile == 0 || i == m_) {
      Step* maxima = tile_max_.data() + ((i - 1) / kTile) * tiles_;
      for (std::size_t t = t0; t < t1; ++t) {
        const std::size_t c0 = t * kTile + 1, c1 = std::min(n_, c0 + kTile - 1);
        maxima[t] = *std::max_element(band + c0, band + c1 + 1);
      }
      std::fill(band + lo, band + hi + 1, Step{0});
    }
  }

  void update_band_max(std::size_t b) {
    const auto first = tile_max_.begin() + static_cast<std::ptrdiff_t>(b * tiles_);
    band_max_[b] = *std::max_element(first, first + static_cast<std::ptrdiff_t>(tiles_));
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

  // Row buffers of the alignment phase, which recomputes one piece of the table at a time.
  struct Buffers {
    std::vector<Step> a, b;
    Scratch scratch;
    Buffers(std::size_t n, std::size_t stride) : a(stride, 0), b(stride, 0), scratch(n) {}
  };

  // The first column of a cursor that covers column j: lo - 1 <= j is 0 or a column checkpoint.
  static std::size_t covering_lo(std::size_t j) { return j / kTile * kTile + 1; }

  // Rows recomputed one after another over columns [lo, hi], from the checkpoint row above and the
  // column checkpoint lo - 1 (a multiple of kTile): h is the current row, above the one before, s the
  // current row's scores (with used pairs forbidden). Uses the pass's buffers: one cursor at a time.
  struct Cursor {
    const FastPass& pass;
    std::size_t lo, hi;
    Step* above;
    Step* h;
    const Step* s = nullptr;
    std::size_t row = 0;
    Step max = 0;
    Cursor(const FastPass& p, std::size_t first, std::size_t last)
        : pass(p), lo(first), hi(last), above(p.buffers_->a.data()), h(p.buffers_->b.data()) {}
    // Positions on checkpoint row k * kTile.
    void start(std::size_t k) {
      const Step* c = pass.checkpoints_.data() + k * pass.stride_;
      std::copy(c + lo - 1, c + hi + 1, h + lo - 1);
      row = k * kTile;
      s = nullptr;
    }
    void advance() {
      std::swap(above, h);
      ++row;
      h[lo - 1] = pass.columns_[row * pass.column_stride_ + (lo - 1) / kTile];
      std::tie(max, s) = pass.compute(row, above, h, lo, hi, pass.buffers_->scratch);
    }
    // Row i (>= 1), from the checkpoint strictly above it.
    void seek(std::size_t i) {
      start((i - 1) / kTile);
      while (row < i) advance();
    }
  };

  // The first cell (row-major) of band b holding `top`, recomputing the band's tiles whose maximum it is.
  Cell first_cell(std::size_t b, Step top) const {
    Cell found{0, 0};
    const std::size_t last = std::min(m_, (b + 1) * kTile);
    for (std::size_t t = 0; t < tiles_; ++t) {
      if (tile_max_[b * tiles_ + t] != top) continue;
      Cursor c(*this, t * kTile + 1, std::min(n_, (t + 1) * kTile));
      c.start(b);
      // a later tile wins only with an earlier row
      while (c.row < last && (found.first == 0 || c.row + 1 < found.first)) {
        c.advance();
        const Step* hit = std::find(c.h + c.lo, c.h + c.hi + 1, top);
        if (hit != c.h + c.hi + 1) {
          found = {c.row, static_cast<std::size_t>(hit - c.h)};
          break;
        }
      }
    }
    if (found.first == 0) throw std::logic_error("tile maximum not found");
    return found;
  }

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

  // The last maximal cell (row-major) reachable from `first` by tight steps, rows streamed downwards
  // over a column range that is doubled while the plateau reaches its right end.
  Cell far_end(Cell first) const {
    for (std::size_t width = 8 * kTile;; width *= 2) {
      const std::size_t lo = covering_lo(first.second - 1);
      Cursor c(*this, lo, std::min(n_, lo - 1 + width));
      c.seek(first.first);
      bool outside = false;
      // Rows are streamed: c holds row i (h) and, after next_row, row i+1 with the row above it.
      struct Grid {
        const FastPass& p;
        Cursor& c;
        Step top_value;
        bool& outside;
        bool in(std::size_t j) const {
          if (j <= c.hi) return true;
          outside = true;
          return false;
        }
        bool top(std::size_t, std::size_t j) const { return in(j) && c.h[j] == top_value; }
        bool right(std::size_t, std::size_t j) const { return in(j) && p.tight_right(c.h, j); }
        void next_row() const { c.advance(); }
        bool down(std::size_t, std::size_t j) const { return in(j) && p.tight_down(c.above, c.h, j); }
        bool diag(std::size_t, std::size_t j) const { return in(j) && p.tight_diag(c.above, c.h, c.s, j); }
      };
      const Cell end = detail::plateau_far_end(first, m_, n_, Grid{*this, c, c.h[first.second], outside});
      if (!outside || c.hi == n_) return end;
    }
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
      return inner(i, j) && value(i, j) > 0 &&
             clamp(detail::saturate(value(i - 1, j - 1) + score(i, j))) == value(i, j);
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
    const std::size_t k = top / kTile;
    w.r0 = k * kTile;
    w.r1 = end.first;
    w.c0 = end.second > cols_left ? end.second - cols_left : 0;
    w.c1 = end.second;
    w.width = w.c1 - w.c0 + 1;
    w.h.assign((w.r1 - w.r0 + 1) * w.width, 0);
    w.s.assign(w.h.size(), 0);
    Cursor c(*this, covering_lo(w.c0), w.c1);  // nothing right of the end can be on its path
    c.start(k);
    std::copy(c.h + w.c0, c.h + w.c1 + 1, w.h.begin());
    while (c.row < w.r1) {
      c.advance();
      const std::size_t r = c.row - w.r0;
      std::copy(c.h + w.c0, c.h + w.c1 + 1, w.h.begin() + static_cast<std::ptrdiff_t>(r * w.width));
      // scores are asked only right of c0 and where the region is (elsewhere h = 0)
      const auto [lo, hi] = region(c.row);
      for (std::size_t j = std::max(w.c0 + 1, lo); j <= std::min(w.c1, hi); ++j) w.s[r * w.width + (j - w.c0)] = c.s[j];
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
    std::size_t reach = kTile;
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

  // Forbids the alignment's pairs, then recomputes the tiles holding them and, tile by tile, every tile
  // whose top row, left column or corner came out changed (a tile whose inputs are unchanged is unchanged).
  void forbid_and_update(const LocalAlignment& a) {
    if (forbidden_.empty()) forbidden_.resize(m_ + 1);
    std::map<std::size_t, std::set<std::size_t>> dirty;  // band -> its tiles to recompute
    for (auto [r, c] : a.pairs) {
      const std::size_t i = r + 1, j = config_.direction == Direction::forward ? c + 1 : n_ - c;
      auto& cols = forbidden_[i];
      cols.insert(std::lower_bound(cols.begin(), cols.end(), j), j);
      dirty[(i - 1) / kTile].insert((j - 1) / kTile);
    }
    while (!dirty.empty()) {  // bands top to bottom, tiles left to right: every input is final when read
      auto node = dirty.extract(dirty.begin());
      const std::size_t b = node.key();
      std::set<std::size_t>& tiles = node.mapped();
      while (!tiles.empty()) {
        const std::size_t t = *tiles.begin();
        tiles.erase(tiles.begin());
        const TileChange change = recompute_tile(b, t);
        if (change.right && t + 1 < tiles_) tiles.insert(t + 1);
        if (change.bottom && b + 1 < bands_) dirty[b + 1].insert(t);
        if (change.corner && b + 1 < bands_ && t + 1 < tiles_) dirty[b + 1].insert(t + 1);
      }
      update_band_max(b);
    }
  }

  struct TileChange {
    bool right = false, bottom = false, corner = false;  // which stored boundaries changed
  };

  // Recomputes tile (b, t) from its stored top row and left column; stores its right column, bottom row
  // and maximum, and says which boundaries changed.
  TileChange recompute_tile(std::size_t b, std::size_t t) {
    const std::size_t lo = t * kTile + 1, hi = std::min(n_, lo + kTile - 1), last = std::min(m_, (b + 1) * kTile);
    const bool right_stored = hi % kTile == 0, bottom_stored = last % kTile == 0;
    TileChange change;
    Step max = 0;
    Cursor c(*this, lo, hi);
    c.start(b);
    while (c.row < last) {
      c.advance();
      max = std::max(max, c.max);
      if (!right_stored) continue;
      Step& stored = columns_[c.row * column_stride_ + hi / kTile];
      if (stored == c.h[hi]) continue;
      stored = c.h[hi];
      change.right = true;
      change.corner = c.row == last && bottom_stored;
    }
    if (bottom_stored) {
      Step* stored = checkpoints_.data() + last / kTile * stride_;
      if (!std::equal(c.h + lo, c.h + hi + 1, stored + lo)) {
        std::copy(c.h + lo, c.h + hi + 1, stored + lo);
        change.bottom = true;
      }
    }
    tile_max_[b * tiles_ + t] = max;
    return change;
  }

  const RowScores& scores_;
  const AlignConfig& config_;
  Steps st_;
  detail::RowKernel kernel_;
  Kernels kernels_;
  std::size_t m_, n_, stride_;
  std::size_t bands_, tiles_;  // tile rows and columns (kTile x kTile cells, the last ones may be smaller)
  std::size_t column_stride_;  // column checkpoints per row
  unsigned threads_;
  // The table is kept only at tile boundaries: from them any tile, or any window, is recomputed exactly.
  std::vector<Step> checkpoints_;                    // H row k * kTile, at k * stride_
  std::vector<Step> columns_;                        // H(i, q * kTile) at i * column_stride_ + q
  std::vector<Step> tile_max_;                       // maximum of tile (b, t) at b * tiles_ + t
  std::vector<Step> band_max_;                       // maximum of each band of tiles
  std::vector<std::vector<std::size_t>> forbidden_;  // per row, sorted pass columns of used pairs
  std::unique_ptr<Buffers> buffers_;
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
  detail::check_config(m, n, config);
  const float scale = checked_scale(config, options);
  const Steps steps = steps_for(config, scale);
  if (m == 0 || n == 0 || config.max_alignments == 0) return {};
  const Kernels kernels = kernels_for(options.isa);
  const auto rows = make_rows(scale, kernels);
  return FastPass(*rows, m, n, config, steps, kernels, resolve(options.threads)).run();
}

template <typename MakeRows>
Score best_pass(std::size_t m, std::size_t n, AlignConfig config, const FastOptions& options, MakeRows make_rows) {
  detail::check_config(m, n, config);
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
  return ScoreSource::function(
      a.size(), b.size(), [s = *this](std::size_t i, std::size_t j) { return s.matrix[s.a[i] * s.alphabet + s.b[j]]; });
}

std::vector<LocalAlignment> fast_local_alignments(const ScoreSource& scores, const AlignConfig& config,
                                                  const FastOptions& options) {
  return run_pass(scores.rows(), scores.cols(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<SourceRows>(scores, config.direction, scale, k);
  });
}

std::vector<LocalAlignment> fast_local_alignments(const LetterScores& scores, const AlignConfig& config,
                                                  const FastOptions& options) {
  validate_letters(scores);
  return run_pass(scores.a.size(), scores.b.size(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<LetterRows>(scores, config.direction, scale, k);
  });
}

Score fast_best_score(const ScoreSource& scores, const AlignConfig& config, const FastOptions& options) {
  return best_pass(scores.rows(), scores.cols(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<SourceRows>(scores, config.direction, scale, k);
  });
}

Score fast_best_score(const LetterScores& scores, const AlignConfig& config, const FastOptions& options) {
  validate_letters(scores);
  return best_pass(scores.a.size(), scores.b.size(), config, options, [&](float scale, const Kernels& k) {
    return std::make_unique<LetterRows>(scores, config.direction, scale, k);
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
