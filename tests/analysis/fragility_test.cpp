// The lognormal fragility fit recovers known parameters from synthetic outcomes, and
// reports separated outcomes instead of a made-up dispersion.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/fragility.h"

namespace ishibashi {
namespace {

TEST(Fragility, RecoversMedianAndDispersionFromSyntheticOutcomes) {
  for (const auto& [median, beta] : {std::pair{0.45, 0.35}, std::pair{1.2, 0.6}}) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> level(std::log(median) - 3 * beta, std::log(median) + 3 * beta);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> x;
    std::vector<int> failed;
    for (int i = 0; i < 4000; ++i) {
      x.push_back(std::exp(level(random)));
      const double p = 0.5 * std::erfc(-std::log(x.back() / median) / beta / std::sqrt(2.0));
      failed.push_back(u(random) < p);
    }
    const FragilityFit fit = fit_lognormal_fragility(x, failed);
    EXPECT_FALSE(fit.degenerate);
    EXPECT_NEAR(fit.median, median, 0.03 * median);
    EXPECT_NEAR(fit.beta, beta, 0.08 * beta);
    EXPECT_NEAR(failure_probability(fit, fit.median), 0.5, 1e-12);
  }
}

TEST(Fragility, SeparatedOrOneSidedOutcomesAreDegenerate) {
  const FragilityFit separated = fit_lognormal_fragility({0.1, 0.2, 0.4, 0.8}, {0, 0, 1, 1});
  EXPECT_TRUE(separated.degenerate);
  EXPECT_GT(separated.median, 0.2);
  EXPECT_LT(separated.median, 0.4);
  EXPECT_TRUE(fit_lognormal_fragility({0.1, 0.2}, {0, 0}).degenerate);
  const FragilityFit mixed = fit_lognormal_fragility({0.1, 0.2, 0.3, 0.4, 0.5}, {0, 1, 0, 1, 1});
  EXPECT_FALSE(mixed.degenerate);
  EXPECT_GT(mixed.beta, 0);
}

}  // namespace
}  // namespace ishibashi
