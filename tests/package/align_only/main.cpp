// The engine on the worked example of smith_waterman.hpp: A = "abedx", B = "ecdab", match +2, mismatch -1,
// gap 1: "ab" with "ab" scores 4, then "ed" with "ecd" scores 3.
#include <cstdio>
#include <string_view>

#include "seqtopo/align/smith_waterman.hpp"

int main() {
  constexpr std::string_view a = "abedx", b = "ecdab";
  const auto scores = seqtopo::align::ScoreSource::function(
      a.size(), b.size(), [&](std::size_t i, std::size_t j) { return a[i] == b[j] ? 2.0F : -1.0F; });
  const auto found = seqtopo::align::local_alignments(scores, {.max_alignments = 2});
  if (found.size() != 2 || found[0].score != 4.0F || found[0].b_begin != 3 || found[1].score != 3.0F ||
      found[1].a_begin != 2 || found[1].b_end != 3) {
    return 1;
  }
  for (const auto& f : found) {
    std::printf("score %.0f: A[%zu, %zu) with B[%zu, %zu)\n", static_cast<double>(f.score), f.a_begin, f.a_end,
                f.b_begin, f.b_end);
  }
  return 0;
}
