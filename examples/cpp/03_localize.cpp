// 03: the kidnapped robot. A map traverse and a later query traverse of part of it, as descriptors (any
// place-recognition network gives such rows); where in the map is each query frame?
//
//   ./03_localize
#include <cstdio>
#include <random>

#include "seqtopo/localize/localize.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

int main() {
  const std::size_t map_frames = 300, dim = 64, first = 120, query_frames = 100;
  std::mt19937 random(3);
  std::normal_distribution<float> step(0.0F, 1.0F), noise(0.0F, 0.8F);
  // The map: a random walk through descriptor space (neighbouring frames look alike, as on a real route).
  seqtopo::DenseMatrix<float> map(map_frames, dim);
  for (std::size_t i = 0; i < map_frames; ++i) {
    for (std::size_t d = 0; d < dim; ++d) map(i, d) = (i ? map(i - 1, d) : 0.0F) + step(random);
  }
  // The query drives map frames 120..219 again, seen with noise.
  seqtopo::DenseMatrix<float> query(query_frames, dim);
  for (std::size_t q = 0; q < query_frames; ++q) {
    for (std::size_t d = 0; d < dim; ++d) query(q, d) = map(first + q, d) + noise(random);
  }

  // Rows = query frames, columns = map frames; cosine distance, S = 1 - kappa D.
  const auto similarity = seqtopo::pipeline::similarity_of_descriptors(query, &map);
  const auto result = seqtopo::localize::localize_sequence(similarity.similarity);
  std::size_t correct = 0, answered = 0;
  for (std::size_t q = 0; q < query_frames; ++q) {
    const auto& f = result.frames[q];
    if (!f.covered) continue;  // every frame has a guess; "in the map" when its confidence is at least 0.5
    ++answered;
    const std::size_t truth = first + q;
    correct += (f.map + 2 >= truth && f.map <= truth + 2) ? 1 : 0;
  }
  std::printf("%zu query frames: %zu in the map, %zu of them within 2 frames of the truth (%zu alignments)\n",
              query_frames, answered, correct, result.alignments.size());
  return correct * 10 >= query_frames * 9 ? 0 : 1;
}
