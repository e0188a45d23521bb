#pragma once
// How often a local alignment this good turns up by chance: the statistics BLAST gives every hit, for the
// scores of one search (a similarity matrix aligned with itself, or a query against a map).
//
// Model (Karlin & Altschul 1990 for ungapped scores; the same form holds empirically for gapped local
// alignment in the logarithmic phase, Arratia & Waterman 1994): in a search of `area` cells, the number of
// chance alignments scoring at least s is Poisson with mean
//   E(s) = K * area * exp(-lambda * s),
// the E-value of a score s; its bit score is (lambda s - ln K) / ln 2.
//
// Fit (Waterman & Vingron 1994, "Rapid and accurate estimates of statistical significance for sequence data
// base searches"; the "island" method of Olsen, Bundschuh & Hwa 1999 and Altschul et al. 2001 counts the same
// clusters): the non-intersecting (declumped) alignments of the search itself, best first, are a sample of
// chance alignments once the few real ones at the top are set aside. Their count above s falls like
// K * area * exp(-lambda s); lambda is the maximum-likelihood estimate from the spacings of the ranked scores
// after the real ones (the Hill estimator of an exponential tail), K the count above each of them. The real
// ones are found by the fit itself: a first fit on the lower three quarters of the ranks, then the fit is
// repeated from `first_rank` or twice
// the number of alignments whose E-value is below `real_e_value` until that number settles, so a search with
// many revisits does not bias lambda. No null model has to be simulated and the statistics are those of
// the sequence's own scores: its descriptors, its length, its aliasing.
//
// Extrapolation: E-values far above the fitted scores are where an error in lambda counts most (a fit from 45
// alignments, lambda to about 15 %, put 5 times too many chance alignments at E <= 0.01 on smooth noise). So
// above the fitted scores' mean s0 the E-value is the posterior predictive one: lambda given the n spacings is
// Gamma(n, n / lambda) (Jeffreys' prior 1 / lambda), and the mean of E(s0) exp(-lambda (s - s0)) over it is
//   E(s) = E(s0) (1 + lambda (s - s0) / n)^-n,
// a Pareto tail that tends to the plug-in exponential as n grows (Gelman et al., Bayesian Data Analysis, the
// exponential-gamma predictive; for the Hill estimator's law, Hill 1975).
#include <cstddef>
#include <span>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/align/score_source.hpp"

namespace seqtopo::significance {

struct ScoreStatistics {
  double lambda = 0;  // [1 / score unit]
  double k = 0;
  double area = 0;                    // [cells] searched
  std::size_t fitted = 0;             // alignments the fit used
  std::size_t first_fitted_rank = 0;  // 1-based rank of the first of them
  // The fitted scores' mean, where the fit's count does not depend on lambda, and the spacings lambda was
  // estimated from (0: lambda taken as exact, the plug-in E-value everywhere).
  double anchor_score = 0;
  double spacings = 0;

  bool valid() const { return lambda > 0 && k > 0 && area > 0; }
  // Expected number of chance alignments scoring >= score in this search (the predictive E-value above the
  // anchor, see above).
  double e_value(double score) const;
  // log2(area / E): BLAST's normalized score, (lambda score - ln K) / ln 2 for an exact lambda.
  double bit_score(double score) const;
  // The score whose E-value is `e_value`.
  double score_at(double e_value) const;
};

struct FitConfig {
  std::size_t first_rank = 10;  // ranks before it are not used in the first fit (the real alignments)
  std::size_t min_fitted = 30;  // fewer usable alignments than this: no fit (valid() is false)
  double real_e_value = 1e-3;   // after the first fit, alignments below this E-value count as real
};

// `scores` are the declumped alignments' scores, best first (non-increasing). Returns an invalid fit when
// there are too few alignments, their scores do not fall with the rank, or the area is empty.
ScoreStatistics fit_declumped_scores(std::span<const double> scores, double area, const FitConfig& config = {});

// Karlin & Altschul's lambda of the cell scores themselves, the positive root of mean(exp(lambda s)) = 1: the
// exact value for ungapped alignments, an upper bound on the gapped one. For searches too small for the fit it
// still makes lambda * score a log-odds in the scores' own scale. 0 when there is no root (no positive score,
// or a mean score that is not negative).
double ungapped_lambda(std::span<const float> scores);

// Diagonals this close [frames] count as one: a chain of shadows, each within reach of the one before, covers
// the wide band of similar diagonals around a revisit in a smooth sequence.
inline constexpr double kShadowReach = 3.0;

// Whether alignment k of a best-first list lies along one found before it: the same direction, their A ranges
// overlapping by half of the shorter or more, and their diagonals (i - j forward, i + j reverse, averaged over
// the pairs) within `reach` frames. Declumping leaves such parallel shadows beside every strong alignment (the
// diagonals next to a revisit score almost as well); they are part of the revisit, not chance, and stay out
// of the fit.
bool shadows_earlier(const std::vector<align::LocalAlignment>& alignments, std::size_t k, double reach);

// Cells the engine searches: rows x cols, or for a self search the pairs with i - j >= min_separation; times two
// when the reverse pass runs too.
double search_area(std::size_t rows, std::size_t cols, bool self, std::size_t min_separation, bool both_passes);

// The probability that an alignment with E-value e is a revisit rather than chance, with the prior odds that make
// one at e = even_odds (the map's cut, max_e_value) as likely one as the other: the Poisson density of chance
// alignments at its score is proportional to e, that of revisits taken as flat over the scores near the cut, so
// P = 1 / (1 + e / even_odds) (an empirical-Bayes local false discovery rate, Efron 2001). exp(-e), the probability
// that no chance alignment scores as well, is near 1 at the cut and made a confident closure of every alignment
// that just passed it. even_odds must be positive.
double revisit_probability(double e, double even_odds);

}  // namespace seqtopo::significance
