// Lognormal fragility curves: the probability of failure at intensity x (e.g. PGA) is
// P(x) = Phi(ln(x / median) / beta), fitted by maximum likelihood to pass/fail outcomes
// (probit regression on ln x, Newton's method), as in Baker (2015), "Efficient analytical
// fragility function fitting using dynamic structural analysis".
#pragma once
#include <string>
#include <vector>

namespace ishibashi {

struct FragilityFit {
  double median = 0;       // intensity of 50 % failure probability (the x units)
  double beta = 0;         // dispersion (standard deviation of ln x at failure)
  double log_likelihood = 0;
  int outcomes = 0, failures = 0;
  // Every run failed, none did, or the outcomes are separated (all failures above all
  // survivals, or at one level mixed and separated elsewhere: the maximum likelihood beta
  // is 0). median and beta are then only bounds (both 0 without any outcome).
  bool degenerate = false;
  // The outcomes' bounds on the median (x units; 0 where there is none): the highest
  // intensity a run stood and the lowest one a run failed at.
  double highest_survival = 0, lowest_failure = 0;
};

// What the median is: "fit" (a curve fitted), or of a degenerate fit where the outcomes
// put it: "above" the highest survival (no run failed), "below" the lowest failure (every
// run failed), "between" the two (all failures above all survivals), "at" the one level
// where they mix; "none" without outcomes.
const char* median_is(const FragilityFit& fit);
// Whether a curve can be drawn: some runs failed and some stood (a degenerate fit's step at
// its median is the likelihood's limit there; with none failed or all, any curve is made up).
bool has_curve(const FragilityFit& fit);
// Why a degenerate fit has no curve and where its median lies, for a user ("no run
// failed: the median lies above 0.6 g, the highest level run"); "" for a fit that is not.
std::string degenerate_reason(const FragilityFit& fit, const std::string& unit);

// intensity: > 0 each; failed: 0 or 1, the same length.
FragilityFit fit_lognormal_fragility(const std::vector<double>& intensity, const std::vector<int>& failed);

double failure_probability(const FragilityFit& fit, double intensity);

// Whether two sets of outcomes (a bridge dry and with mortar, on the same records and
// levels) follow one fragility curve: the likelihood-ratio statistic 2 (l_a + l_b - l_ab)
// of a curve fitted to each against one fitted to both, and its p-value, the chance of a
// statistic this large if they share one curve (chi-square, 2 degrees of freedom:
// exp(-statistic / 2); Wilks' theorem, an approximation that needs tens of outcomes per
// set). A degenerate fit's likelihood is its supremum: 1, or the mixed level's own.
struct FragilityComparison {
  double statistic = 0;
  double p_value = 1;
};
FragilityComparison compare_fragilities(const std::vector<double>& intensity_a, const std::vector<int>& failed_a,
                                        const std::vector<double>& intensity_b, const std::vector<int>& failed_b);

}  // namespace ishibashi
