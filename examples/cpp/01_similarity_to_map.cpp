// 01: a similarity matrix in, a topological map out (mapping paper, section IV), with the library alone.
//
// A robot drives 120 frames and frames 80..119 revisit the places of frames 20..59. Any sensor that can
// compare two readings gives such a matrix; here it is made up: similar where the places are the same.
//
//   ./01_similarity_to_map
#include <cstdio>
#include <random>

#include "seqtopo/mapping/map_builder.hpp"

int main() {
  const std::size_t n = 120;
  std::mt19937 random(7);
  std::normal_distribution<float> noise(0.0F, 0.05F);
  const auto place = [](std::size_t k) { return k >= 80 ? k - 60 : k; };  // frame 80 sees the place of frame 20
  seqtopo::SimilarityMatrix s(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      const float d = static_cast<float>(place(i) > place(j) ? place(i) - place(j) : place(j) - place(i));
      s(i, j) = s(j, i) = 1.0F / (1.0F + d) + noise(random);
    }
  }

  const seqtopo::mapping::MapResult result = seqtopo::mapping::build_map(s);  // the default settings
  std::printf("%zu images, %zu alignments, %zu places, %zu junctions\n", n, result.alignments.size(),
              result.map.places.size(), result.map.junctions.size());
  for (const auto& a : result.alignments) {
    std::printf("revisit: images %zu..%zu match %zu..%zu (%s, score %.1f)\n", a.a_begin, a.a_end - 1, a.b_begin,
                a.b_end - 1, a.direction == seqtopo::align::Direction::forward ? "forward" : "reverse",
                static_cast<double>(a.score));
  }
  std::size_t correct = 0;
  for (const auto& p : result.pruning.pairs) correct += place(p.i) == place(p.j) ? 1 : 0;
  std::printf("%zu loop-closure pairs, %zu of them on the same place\n", result.pruning.pairs.size(), correct);
  return result.pruning.pairs.empty() ? 1 : 0;
}
