// The striped row kernel's body (fast_kernels.hpp: StripedJob), written once over a traits type W (one per
// instruction set and element width, in fast_striped_x86.cpp). Deliberately without an include guard:
// fast_striped_x86.cpp includes it once per instruction set, inside a namespace of its own and with
// SEQTOPO_STRIPED_ISA naming the target, because GCC inlines target-specific intrinsics only into
// functions compiled for that target (a plain template would not do).
//
// A block of B = 32 x lanes columns holds, in vector s, column s of each of its `lanes` tiles. A row:
//  1. pass 1, block by block: for s = 0 .. 31, T = max(H(i-1, j-1) + S, H(i-1, j) - gap_a) from the row
//     above (the diagonal is vector s - 1 of the previous row; for s = 0, its vector 31 shifted up one
//     lane, H(i-1, b0-1) entering lane 0), then H = max(min(cap, T), F) with F = H(vector s - 1) -
//     gap_b, the gap_b step inside each tile. The cap commutes with F because F <= cap always (F
//     comes from a cell <= cap, minus gap_b >= 0; with gap_b = 0, F equals a cell, still <= cap), so
//     the serial chain from vector to vector is one max and one subtraction. The blocks' chains are
//     independent of each other and overlap in the out-of-order core.
//  2. pass 2, block by block from left to right: F leaving each tile's last column and entering the
//     next tile's first. carry() computes it exactly for every lane at once (a decayed running maximum
//     over the lanes) and applies it; masked blocks use the classic lazy-F loop (Farrar 2007).
// A block only partly searched (the self region's edge) takes a mask instead of the cap: cap where
// the column is searched, 0 elsewhere, applied to H in both passes, so such columns are exactly 0 as
// the row kernel leaves them. Columns past the strip's end (the last block's padding) need no mask.

// The row's gaps and cap as vectors, and what gaps cost in the cross-lane scan (in unsigned lanes of H,
// where one saturating subtraction takes anything up to kMax): decay[r] = (2^r) x 32 x gap_b (a step of
// 2^r lanes), entry[l] = gap_b + 32 x gap_b x l (from the block's left edge to vector 0 of lane l), both
// saturated at kMax.
template <class W>
struct StripedGaps {
  typename W::V gap_a, gap_b, cap, entry;
  typename W::V decay[5];
  int gap_b_value;
};

// Pass 1 over N consecutive blocks (1, or 2 interleaved: two independent F chains in one loop, since
// one block's loop is longer than the out-of-order window and its chain is the bound): every cell from
// the row above and from F inside its own tile. F starts at 0, which is as good as -inf since every
// H >= 0, and stays >= 0 (floor_sub), so H = max(min(cap, T), F) needs no separate max with 0; without
// a cap below kMax the min is saturation's already. diag_left[n] is a rep. best[n] gets each block's
// maximum so far. score[n] is block n's vector 0 of scores: in its own layout (vector s at s x lanes), or
// with kScore8 (int16 lanes only) in the int8 layout (vector s at s x 2 lanes, widened on loading).
template <class W, bool kMasked, bool kCapped, int N, bool kScore8>
[[gnu::target(SEQTOPO_STRIPED_ISA), gnu::always_inline]] inline void first_pass(
    const typename W::E* prev, typename W::E* cur, const void* const* score, const typename W::E* mask,
    const int* diag_left, const StripedGaps<W>& g, typename W::V* best) {
  using V = typename W::V;
  constexpr std::size_t L = W::kLanes, S = kTileSide, B = L * S;
  V f[N], diag[N];
  for (int n = 0; n < N; ++n) {
    best[n] = W::zero();
    f[n] = W::zero();
    diag[n] = W::shift_up(W::load(prev + n * B + (S - 1) * L), diag_left[n]);
  }
  for (std::size_t s = 0; s < S; ++s) {
    for (int n = 0; n < N; ++n) {
      const std::size_t at = n * B + s * L;
      const V up = W::load(prev + at);
      V sc;
      if constexpr (kScore8) {
        sc = W::widen_scores(static_cast<const std::int8_t*>(score[n]) + s * 2 * L);
      } else {
        sc = W::load(static_cast<const typename W::E*>(score[n]) + s * L);
      }
      const V t = W::max(W::adds(diag[n], sc), W::subs(up, g.gap_a));
      V h;
      if constexpr (kMasked) {
        h = W::min(W::max(t, f[n]), W::load(mask + s * L));
      } else if constexpr (kCapped) {
        h = W::max(W::min(t, g.cap), f[n]);
      } else {
        h = W::max(t, f[n]);
      }
      W::store(cur + at, h);
      best[n] = W::max(best[n], h);
      f[n] = W::floor_sub(h, g.gap_b);
      diag[n] = up;
    }
  }
}

// A decayed running maximum over the lanes of u (H in unsigned lanes): u(l) = max over l' <= l of
// u(l') - 32 gap_b (l - l') (floored at 0), in log2(lanes) shift steps; the lanes shifted in are 0.
template <class W>
[[gnu::target(SEQTOPO_STRIPED_ISA), gnu::always_inline]] inline typename W::V lane_scan(typename W::V u,
                                                                                        const StripedGaps<W>& g) {
  constexpr std::size_t L = W::kLanes;
  u = W::umax(u, W::usub(W::template shift<1>(u), g.decay[0]));
  u = W::umax(u, W::usub(W::template shift<2>(u), g.decay[1]));
  u = W::umax(u, W::usub(W::template shift<4>(u), g.decay[2]));
  if constexpr (L > 8) u = W::umax(u, W::usub(W::template shift<8>(u), g.decay[3]));
  if constexpr (L > 16) u = W::umax(u, W::usub(W::template shift<16>(u), g.decay[4]));
  return u;
}

// Pass 2 over a whole block (not masked), once the block on its left is final (left = H(i, b0 - 1)).
// Pass 1 left, in every lane, H(s) = the best path that enters the tile from above; the true H(s) is
// max(that, F - s gap_b) with F the gap_b path entering the lane at vector 0 from the left:
// F(l) = max(H(31, l - 1) - gap_b, F(l - 1) - 32 gap_b), F(0) = left - gap_b, where H(31, l - 1) is
// pass 1's value (the final one is max(it, F(l - 1) - 31 gap_b), already in the second term). That
// recursion is the lane scan; then vector s of lane l gets F - s gap_b: always for s < steps (a branch
// there would be mispredicted), beyond only until no lane improves (every later cell already holds at
// least that, as pass 1 put H(s + 1) >= H(s) - gap_b in every lane). Returns the maximum of the cells it
// touched; `further` counts the blocks where F still raised a cell after the first `steps` vectors.
template <class W>
[[gnu::target(SEQTOPO_STRIPED_ISA), gnu::always_inline]] inline typename W::V carry(typename W::E* cur, int left,
                                                                                    const StripedGaps<W>& g,
                                                                                    std::size_t steps,
                                                                                    std::size_t& further) {
  using V = typename W::V;
  constexpr std::size_t L = W::kLanes, S = kTileSide;
  V best = W::zero();
  const V from_lanes = lane_scan<W>(W::template shift<1>(W::usub(W::to_h(W::load(cur + (S - 1) * L)), g.gap_b)), g);
  V f = W::from_h(W::umax(from_lanes, W::usub(W::set1(left), g.entry)));
  std::size_t s = 0;
  for (; s < steps; ++s) {
    const V h = W::max(W::load(cur + s * L), f);
    W::store(cur + s * L, h);
    best = W::max(best, h);
    f = W::floor_sub(f, g.gap_b);
  }
  for (bool first = true; s < S; ++s, first = false) {
    V h = W::load(cur + s * L);
    if (!W::any(W::cmpgt(f, h))) break;
    further += first;
    h = W::max(h, f);
    W::store(cur + s * L, h);
    best = W::max(best, h);
    f = W::floor_sub(f, g.gap_b);
  }
  return best;
}

// Pass 2 over a masked block: the lazy-F loop, F carried vector by vector and across lanes (each wrap to
// the next lane shifts in 0, so it ends after at most `lanes` wraps even with gap_b = 0), cut to 0 by
// the mask where a column is not searched.
template <class W>
[[gnu::target(SEQTOPO_STRIPED_ISA), gnu::always_inline]] inline typename W::V carry_masked(typename W::E* cur,
                                                                                           const typename W::E* mask,
                                                                                           int left,
                                                                                           const StripedGaps<W>& g) {
  using V = typename W::V;
  constexpr std::size_t L = W::kLanes, S = kTileSide;
  V best = W::zero();
  V f = W::shift_up(W::floor_sub(W::load(cur + (S - 1) * L), g.gap_b), std::max(left - g.gap_b_value, 0) - W::kOffset);
  for (;;) {
    for (std::size_t s = 0; s < S; ++s) {
      f = W::min(f, W::load(mask + s * L));
      V h = W::load(cur + s * L);
      if (!W::any(W::cmpgt(f, h))) return best;
      h = W::max(h, f);
      W::store(cur + s * L, h);
      best = W::max(best, h);
      f = W::floor_sub(f, g.gap_b);
    }
    f = W::shift_up(f, -W::kOffset);
  }
}

// Lanes l of vector s with lo <= 32 l + s < hi get cap, the others 0 (lo, hi relative to the block).
// With lo = 32 q + r, the first such lane is q + 1 for s < r and q for s >= r; likewise for hi.
template <class W>
[[gnu::target(SEQTOPO_STRIPED_ISA), gnu::always_inline]] inline void striped_mask(typename W::E* mask, int lo, int hi,
                                                                                  typename W::V cap) {
  using V = typename W::V;
  constexpr int S = static_cast<int>(kTileSide);
  const V lane = W::lane_index();
  const V below_lo[2] = {W::cmpgt(W::set1(lo / S + 1), lane), W::cmpgt(W::set1(lo / S), lane)};
  const V below_hi[2] = {W::cmpgt(W::set1(hi / S + 1), lane), W::cmpgt(W::set1(hi / S), lane)};
  for (int s = 0; s < S; ++s) {
    // searched: not below lo, and below hi
    const V searched = W::select(below_hi[s >= hi % S], cap, W::zero());
    W::store(mask + static_cast<std::size_t>(s) * W::kLanes, W::select(below_lo[s >= lo % S], W::zero(), searched));
  }
}

// The row: pass 1 over every touched block (independent of each other, so the out-of-order core overlaps
// their serial F chains), then pass 2 block by block from left to right (each needs the final last
// column of the block on its left), with the tiles' maxima and right columns.
template <class W, bool kScore8>
[[gnu::target(SEQTOPO_STRIPED_ISA)]] std::int16_t striped_row_of(const StripedJob& job) {
  using E = typename W::E;
  using V = typename W::V;
  constexpr std::size_t L = W::kLanes, S = kTileSide, B = L * S;
  const E* const prev = static_cast<const E*>(job.prev);
  E* const cur = static_cast<E*>(job.cur);
  // Block k's scores: block k of the row's own layout, or (kScore8) half k % 2 of the int8 layout's
  // block k / 2, which holds the same tiles in twice the lanes.
  auto score_of = [&job](std::size_t k) -> const void* {
    if constexpr (kScore8) {
      return static_cast<const std::int8_t*>(job.score) + k / 2 * 2 * B + k % 2 * L;
    } else {
      return static_cast<const E*>(job.score) + k * B;
    }
  };
  StripedGaps<W> g;
  const long gap_b = std::min<int>(job.gap_b, W::kStep), tile_gap = static_cast<long>(S) * gap_b;
  g.gap_a = W::set1(std::min<int>(job.gap_a, W::kStep));
  g.gap_b = W::set1(static_cast<int>(gap_b));
  g.gap_b_value = static_cast<int>(gap_b);
  g.cap = W::set1(std::min<int>(job.cap, W::kMax) - W::kOffset);
  const bool capped = job.cap < W::kMax;
  for (std::size_t r = 0; r < 5; ++r) g.decay[r] = W::set1(static_cast<int>(std::min<long>(tile_gap << r, W::kMax)));
  alignas(32) E entry[L];
  for (std::size_t l = 0; l < L; ++l) {
    entry[l] = static_cast<E>(std::min<long>(gap_b + tile_gap * static_cast<long>(l), W::kMax));
  }
  g.entry = W::load(entry);
  const std::size_t width = job.width, rlo = job.rlo, rhi = job.rhi;
  std::int16_t* const tile_max = job.tile_max;
  std::int16_t* const columns = job.columns;
  // Only the first and the last touched block can be partly searched: their masks. A block whose searched
  // columns run to the strip's end needs none: columns past the strip's end are padding with scores 0,
  // whose cells never exceed a real cell above or left of them (every step into them costs >= 0) and
  // reach nothing but padding; only the maximum of the tile they share with real columns is recomputed.
  const std::size_t first = rlo / B, end = (rhi + B - 1) / B;
  auto masked = [&](std::size_t k) { return k * B < rlo || ((k + 1) * B > rhi && rhi < width); };
  alignas(32) E masks[2][B];
  auto mask_of = [&](std::size_t k) -> E* { return masks[k == first ? 0 : 1]; };
  for (std::size_t k : {first, end - 1}) {
    if (masked(k)) {
      striped_mask<W>(mask_of(k), static_cast<int>(std::max(rlo, k * B) - k * B),
                      static_cast<int>(std::min(rhi, k * B + B) - k * B), g.cap);
    }
  }
  V row_best = W::zero();
  V partial_best = W::zero();  // pass 1's maximum of the strip's last block if it is partial
  for (std::size_t k = first; k < end;) {
    // rep(H(i - 1, b0 - 1)): the last lane of the block on the left (rep(0) if it was not touched)
    const int diag_left[2] = {k == 0 ? std::min<int>(job.diag_left, W::kMax) - W::kOffset : prev[k * B - 1],
                              prev[(k + 1) * B - 1]};
    const void* const score[2] = {score_of(k), score_of(k + 1)};
    V best[2];
    int blocks = 1;
    if (masked(k)) {
      first_pass<W, true, true, 1, kScore8>(prev + k * B, cur + k * B, score, mask_of(k), diag_left, g, best);
    } else if (k + 1 < end && !masked(k + 1)) {
      blocks = 2;
      if (capped) {
        first_pass<W, false, true, 2, kScore8>(prev + k * B, cur + k * B, score, nullptr, diag_left, g, best);
      } else {
        first_pass<W, false, false, 2, kScore8>(prev + k * B, cur + k * B, score, nullptr, diag_left, g, best);
      }
    } else if (capped) {
      first_pass<W, false, true, 1, kScore8>(prev + k * B, cur + k * B, score, nullptr, diag_left, g, best);
    } else {
      first_pass<W, false, false, 1, kScore8>(prev + k * B, cur + k * B, score, nullptr, diag_left, g, best);
    }
    for (int n = 0; n < blocks; ++n, ++k) {
      row_best = W::max(row_best, best[n]);
      if ((k + 1) * B <= width) {
        W::widen_max(tile_max + k * L, best[n]);
      } else {
        partial_best = best[n];  // its tiles are maxed after pass 2
      }
    }
  }
  const std::size_t steps = job.carry ? job.carry->steps : 8;  // pass 2's unconditional steps
  std::size_t further = 0;
  for (std::size_t k = first; k < end; ++k) {
    const std::size_t b0 = k * B;
    const int left = k == 0 ? std::min<int>(job.left, W::kMax) : cur[b0 - 1] + W::kOffset;  // H(i, b0 - 1)
    const V best =
        masked(k) ? carry_masked<W>(cur + b0, mask_of(k), left, g) : carry<W>(cur + b0, left, g, steps, further);
    row_best = W::max(row_best, best);
    if (b0 + B <= width) {
      W::widen_max(tile_max + k * L, best);
      if (columns) W::widen_store(columns + k * L, W::load(cur + b0 + (S - 1) * L));
      continue;
    }
    // The strip's last block, partial: the tile shared with padding is maxed over its real columns only,
    // and only whole tiles have a right column.
    const std::size_t real = width - b0, whole = real / S;
    alignas(32) std::int16_t lanes[L];
    W::widen_store(lanes, W::max(best, partial_best));
    for (std::size_t l = 0; l < whole; ++l) tile_max[k * L + l] = std::max(tile_max[k * L + l], lanes[l]);
    if (real % S != 0) {
      std::int16_t& m = tile_max[k * L + whole];
      for (std::size_t c = 0; c < real % S; ++c) {
        m = std::max(m, static_cast<std::int16_t>(cur[b0 + c * L + whole] + W::kOffset));
      }
    }
    if (columns) {
      W::widen_store(lanes, W::load(cur + b0 + (S - 1) * L));
      std::copy(lanes, lanes + whole, columns + k * L);
    }
  }
  if (CarryHint* hint = job.carry) {
    hint->blocks += end - first;
    hint->further += further;
    if (hint->blocks >= 256) {
      if (hint->further * 4 > hint->blocks && hint->steps < 16) hint->steps *= 2;
      if (hint->further * 32 < hint->blocks && hint->steps > 2) hint->steps /= 2;
      hint->blocks = hint->further = 0;
    }
  }
  return static_cast<std::int16_t>(W::hmax(row_best));
}

// The row, with the scores in the layout job.score8 says (int8 scores only reach int16 lanes).
template <class W>
[[gnu::target(SEQTOPO_STRIPED_ISA)]] std::int16_t striped_row(const StripedJob& job) {
  if constexpr (sizeof(typename W::E) == 2) {
    if (job.score8) return striped_row_of<W, true>(job);
  }
  return striped_row_of<W, false>(job);
}
