#include "seqtopo/align/letter_problem.hpp"

#include <random>

namespace seqtopo::align {

LetterProblem random_letter_problem(std::size_t length, unsigned seed) {
  LetterProblem p;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> letter(0, static_cast<int>(LetterProblem::letters) - 1), mismatch(-4, -1);
  p.a.resize(length);
  p.b.resize(length);
  for (auto& x : p.a) x = static_cast<std::uint8_t>(letter(rng));
  for (auto& x : p.b) x = static_cast<std::uint8_t>(letter(rng));
  constexpr std::size_t n = LetterProblem::letters;
  p.matrix.assign(n * n, 0.0F);
  for (std::size_t x = 0; x < n; ++x) {
    for (std::size_t y = 0; y <= x; ++y) {
      p.matrix[x * n + y] = p.matrix[y * n + x] = static_cast<float>(x == y ? 5 : mismatch(rng));
    }
  }
  for (auto x : p.a) p.a_text.push_back(LetterProblem::alphabet[x]);
  for (auto x : p.b) p.b_text.push_back(LetterProblem::alphabet[x]);
  return p;
}

}  // namespace seqtopo::align
