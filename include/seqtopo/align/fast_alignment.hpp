#pragma once
// The fast alignment engine: the same alignments as local_alignments() (smith_waterman.hpp), computed
// with striped integer SIMD arithmetic (8-bit lanes while the scores fit, else 16-bit) and no traceback
// table: H is kept only on the boundaries of 32 x 32 tiles, 1/8 byte per cell (docs/engine.md).
//
// Scores are quantized once: every score, gap, cap and threshold becomes round(x * scale) "steps"
// (int16, ties to even, saturating at +-32767; a NaN score counts as -32767). On those integer-valued
// inputs the result is identical (scores, ranges, pairs, order) to the scalar engine run on
// quantized(source, scale) with quantized(config, scale); reported scores are steps / scale.
//
// Worked example: with cap 40 and the default scale, scale = 512 (40 * 512 = 20480 <= 32767 < 40 * 1024),
// so a similarity of 0.3 becomes 154 steps (153.6 rounded) and a reported 40 is 20480 steps / 512.
//
// Overflow: with a cap, cap * scale must fit in int16 (else std::invalid_argument); every cumulative
// score is then bounded and saturation cannot change a result. Without a cap, the fill throws
// std::invalid_argument as soon as a cumulative score reaches 32767 steps: set a cap or a smaller scale.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::align {

// Instruction sets of the kernel; `best` is whatever this CPU supports (best_isa()).
enum class Isa { scalar, sse41, avx2, best };
std::string_view to_string(Isa isa);

struct FastOptions {
  // Score units -> int16 steps. 0 chooses (fast_scale()): with a cap, the largest power of two with
  // cap * scale <= 32767; without one, 1 if gaps and threshold are whole numbers (integer scoring
  // schemes), else the power of two putting max(1, gap_a, gap_b, threshold) at 128..255 steps.
  float scale = 0;
  // Worker threads of the fill (column strips in a wavefront) and of the two passes of
  // fast_local_alignments_both; 0 = all cores. The result never depends on it.
  unsigned threads = 0;
  // An ISA this CPU lacks falls back to the best one it has.
  Isa isa = Isa::best;
};

// One pass (config.direction). Throws std::invalid_argument like local_alignments(), and on a scale
// that is not finite and positive, or a cap that does not fit in int16 steps.
std::vector<LocalAlignment> fast_local_alignments(const ScoreSource& scores, const AlignConfig& config,
                                                  const FastOptions& options = {});
// Forward and reverse passes merged exactly as local_alignments_both() merges them.
std::vector<LocalAlignment> fast_local_alignments_both(const ScoreSource& scores, AlignConfig config,
                                                       const FastOptions& options = {});

// The best cell value of one pass (config.direction; threshold and max_alignments ignored), from a
// score-only fill: the cheapest question the engine answers.
Score fast_best_score(const ScoreSource& scores, const AlignConfig& config, const FastOptions& options = {});

// Letters and a substitution matrix instead of a score source: score(i, j) = matrix[a[i] * alphabet + b[j]].
// The engine precomputes one int16 row per letter (a query profile), so a row costs no score reads.
// Not owned: the caller keeps the spans alive.
struct LetterScores {
  std::span<const std::uint8_t> a, b;  // letters in [0, alphabet)
  std::span<const float> matrix;       // alphabet x alphabet, row-major
  std::size_t alphabet = 0;
  ScoreSource source() const;  // the same scores as a ScoreSource (for the scalar engine)
};
std::vector<LocalAlignment> fast_local_alignments(const LetterScores& scores, const AlignConfig& config,
                                                  const FastOptions& options = {});
Score fast_best_score(const LetterScores& scores, const AlignConfig& config, const FastOptions& options = {});

// The scale the engine uses for these settings (options.scale, or the automatic choice above).
float fast_scale(const AlignConfig& config, const FastOptions& options = {});
// The integer-valued scores (in steps) the fast engine sees, for running the scalar engine on the same input.
ScoreSource quantized(const ScoreSource& scores, float scale);
// Gaps, cap and threshold in steps, as the fast engine uses them.
AlignConfig quantized(const AlignConfig& config, float scale);

// What this CPU supports.
Isa best_isa();

}  // namespace seqtopo::align
