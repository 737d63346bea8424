// Lognormal fragility curves: the probability of failure at intensity x (e.g. PGA) is
// P(x) = Phi(ln(x / median) / beta), fitted by maximum likelihood to pass/fail outcomes
// (probit regression on ln x, Newton's method), as in Baker (2015), "Efficient analytical
// fragility function fitting using dynamic structural analysis".
#pragma once
#include <vector>

namespace ishibashi {

struct FragilityFit {
  double median = 0;       // intensity of 50 % failure probability (the x units)
  double beta = 0;         // dispersion (standard deviation of ln x at failure)
  double log_likelihood = 0;
  int outcomes = 0, failures = 0;
  // Every run failed, none did, or the outcomes are separated (all failures above all
  // survivals: the maximum likelihood beta is 0). median and beta are then only bounds.
  bool degenerate = false;
};

// intensity: > 0 each; failed: 0 or 1, the same length.
FragilityFit fit_lognormal_fragility(const std::vector<double>& intensity, const std::vector<int>& failed);

double failure_probability(const FragilityFit& fit, double intensity);

}  // namespace ishibashi
