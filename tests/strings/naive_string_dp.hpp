#pragma once
// Plain O(n * m) dynamic programming references for the string algorithms, written for clarity.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/strings/costs.hpp"

namespace seqtopo::test_support {

// Full-table weighted global alignment, lexicographic (cost, differences), optionally restricted to the
// diagonals lo <= j - i <= hi. Returns {cost, differences}; cost = +inf when (n, m) is unreachable.
inline std::pair<double, std::size_t> naive_global(std::string_view p, std::string_view t, const strings::EditCosts& c,
                                                   std::int64_t lo = std::numeric_limits<std::int64_t>::min(),
                                                   std::int64_t hi = std::numeric_limits<std::int64_t>::max()) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::size_t n = p.size(), m = t.size();
  std::vector<std::vector<std::pair<double, std::size_t>>> D(
      n + 1, std::vector<std::pair<double, std::size_t>>(m + 1, {inf, 0}));
  auto inside = [&](std::size_t i, std::size_t j) {
    const auto d = static_cast<std::int64_t>(j) - static_cast<std::int64_t>(i);
    return d >= lo && d <= hi;
  };
  for (std::size_t i = 0; i <= n; ++i) {
    for (std::size_t j = 0; j <= m; ++j) {
      if (!inside(i, j)) continue;
      if (i == 0 && j == 0) {
        D[0][0] = {0.0, 0};
        continue;
      }
      std::pair<double, std::size_t> best{inf, 0};
      auto offer = [&](std::pair<double, std::size_t> from, double cost, bool diff) {
        if (from.first == inf) return;
        const std::pair<double, std::size_t> cand{from.first + cost, from.second + (diff ? 1 : 0)};
        if (cand < best) best = cand;
      };
      if (i > 0 && j > 0) offer(D[i - 1][j - 1], c.substitution(p[i - 1], t[j - 1]), p[i - 1] != t[j - 1]);
      if (i > 0) offer(D[i - 1][j], c.deletion, true);
      if (j > 0) offer(D[i][j - 1], c.insertion, true);
      D[i][j] = best;
    }
  }
  return D[n][m];
}

// Unit-cost edit distance.
inline std::size_t naive_edit_distance(std::string_view p, std::string_view t) {
  std::vector<std::size_t> row(t.size() + 1);
  for (std::size_t j = 0; j <= t.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= p.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= t.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({up + 1, row[j - 1] + 1, diag + (p[i - 1] == t[j - 1] ? 0U : 1U)});
      diag = up;
    }
  }
  return row[t.size()];
}

// Infix edit distance: for each end j of T, the fewest differences of P against some T[s, j).
inline std::vector<std::size_t> naive_infix(std::string_view p, std::string_view t) {
  std::vector<std::size_t> row(t.size() + 1, 0);  // free start anywhere on row 0
  for (std::size_t i = 1; i <= p.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= t.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({up + 1, row[j - 1] + 1, diag + (p[i - 1] == t[j - 1] ? 0U : 1U)});
      diag = up;
    }
  }
  return row;
}

inline std::size_t naive_lcs(std::string_view p, std::string_view t) {
  std::vector<std::vector<std::size_t>> L(p.size() + 1, std::vector<std::size_t>(t.size() + 1, 0));
  for (std::size_t i = 1; i <= p.size(); ++i) {
    for (std::size_t j = 1; j <= t.size(); ++j) {
      L[i][j] = p[i - 1] == t[j - 1] ? L[i - 1][j - 1] + 1 : std::max(L[i - 1][j], L[i][j - 1]);
    }
  }
  return L[p.size()][t.size()];
}

// Indel distance (insertions and deletions only), by its own DP.
inline std::size_t naive_indel_distance(std::string_view p, std::string_view t) {
  std::vector<std::vector<std::size_t>> D(p.size() + 1, std::vector<std::size_t>(t.size() + 1, 0));
  for (std::size_t i = 0; i <= p.size(); ++i) D[i][0] = i;
  for (std::size_t j = 0; j <= t.size(); ++j) D[0][j] = j;
  for (std::size_t i = 1; i <= p.size(); ++i) {
    for (std::size_t j = 1; j <= t.size(); ++j) {
      D[i][j] = std::min(D[i - 1][j] + 1, D[i][j - 1] + 1);
      if (p[i - 1] == t[j - 1]) D[i][j] = std::min(D[i][j], D[i - 1][j - 1]);
    }
  }
  return D[p.size()][t.size()];
}

// Fingerprint-like random strings: edges 'v' and colours from the first `colours` classes.
inline std::string random_fingerprint(std::mt19937& rng, std::size_t min_len, std::size_t max_len, int colours = 6) {
  std::uniform_int_distribution<std::size_t> len(min_len, max_len);
  std::uniform_int_distribution<int> sym(0, colours);
  std::string s(len(rng), 'v');
  for (char& c : s) {
    const int x = sym(rng);
    c = x == colours ? 'v' : static_cast<char>('A' + x);
  }
  return s;
}

// A noisy copy: each symbol kept, substituted, deleted, or followed by an insertion.
inline std::string mutate(std::mt19937& rng, std::string_view s, double rate, int colours = 6) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> sym(0, colours);
  auto random_symbol = [&] {
    const int x = sym(rng);
    return x == colours ? 'v' : static_cast<char>('A' + x);
  };
  std::string out;
  for (char c : s) {
    const double x = u(rng);
    if (x < rate / 3) continue;
    out.push_back(x < 2 * rate / 3 ? random_symbol() : c);
    if (x > 1 - rate / 3) out.push_back(random_symbol());
  }
  return out;
}

}  // namespace seqtopo::test_support
