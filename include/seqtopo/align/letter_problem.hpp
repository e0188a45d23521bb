#pragma once
// A random protein-like alignment problem, the common input of the engine benchmarks (bench/bench_engine,
// `seqtopo bench align`) and of the tools they are compared with (parasail, EMBOSS matcher): two sequences
// over 20 letters and a symmetric substitution matrix, +5 on the diagonal and -4 .. -1 elsewhere.
// Deterministic by seed.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace seqtopo::align {

struct LetterProblem {
  static constexpr std::size_t letters = 20;
  static constexpr const char* alphabet = "ARNDCQEGHILKMFPSTWYV";
  std::vector<std::uint8_t> a, b;  // letter indices
  std::string a_text, b_text;      // the same as text over `alphabet`
  std::vector<float> matrix;       // letters x letters, row-major
  int score(std::size_t x, std::size_t y) const { return static_cast<int>(matrix[x * letters + y]); }
};

LetterProblem random_letter_problem(std::size_t length, unsigned seed);

}  // namespace seqtopo::align
