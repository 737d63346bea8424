// The lognormal fragility fit recovers known parameters from synthetic outcomes, and
// reports separated outcomes instead of a made-up dispersion.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/batch/fragility.h"

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
  const FragilityFit none = fit_lognormal_fragility({}, {});
  EXPECT_TRUE(none.degenerate);
  EXPECT_EQ(none.median, 0.0);  // not NaN: a sweep stopped before a variant's first run
  // Mixed at one level only (five members at 0.6 g, two fail), separated elsewhere: beta
  // has no finite maximum either. The median is that level, and the likelihood's
  // supremum is 0.4^2 0.6^3 (the level's own failure share).
  const FragilityFit one_level = fit_lognormal_fragility({0.2, 0.4, 0.6, 0.6, 0.6, 0.6, 0.6, 0.8, 1.0}, {0, 0, 1, 1, 0, 0, 0, 1, 1});
  EXPECT_TRUE(one_level.degenerate);
  EXPECT_EQ(one_level.beta, 0.0);
  EXPECT_NEAR(one_level.median, 0.6, 1e-12);
  EXPECT_NEAR(one_level.log_likelihood, 2 * std::log(0.4) + 3 * std::log(0.6), 1e-12);
  // The same with that level's runs a bit apart, as records scaled to one level are.
  const double below = std::nextafter(0.6, 0.0), above = std::nextafter(0.6, 1.0);
  for (const auto& [at_failure, at_survival] : {std::pair{below, above}, std::pair{above, below}}) {
    const FragilityFit apart = fit_lognormal_fragility({0.2, 0.4, at_failure, at_failure, at_survival, 0.6, 0.6, 0.8, 1.0},
                                                       {0, 0, 1, 1, 0, 0, 0, 1, 1});
    EXPECT_TRUE(apart.degenerate);
    EXPECT_NEAR(apart.median, 0.6, 1e-12);
    EXPECT_NEAR(apart.log_likelihood, 2 * std::log(0.4) + 3 * std::log(0.6), 1e-12);
  }
  const FragilityFit mixed = fit_lognormal_fragility({0.1, 0.2, 0.3, 0.4, 0.5}, {0, 1, 0, 1, 1});
  EXPECT_FALSE(mixed.degenerate);
  EXPECT_GT(mixed.beta, 0);
  EXPECT_EQ(degenerate_reason(mixed, "g"), "");
}

// What a degenerate fit tells its user: which case, and where its outcomes put the median.
TEST(Fragility, ADegenerateFitSaysWhereTheMedianLies) {
  using ::testing::HasSubstr;
  EXPECT_EQ(degenerate_reason(fit_lognormal_fragility({0.2, 0.6}, {0, 0}), "g"),
            "no run failed: the median lies above 0.6 g, the highest level run");
  EXPECT_EQ(degenerate_reason(fit_lognormal_fragility({0.2, 0.6}, {1, 1}), "g"),
            "every run failed: the median lies below 0.2 g, the lowest level run");
  EXPECT_THAT(degenerate_reason(fit_lognormal_fragility({0.1, 0.2, 0.4, 0.8}, {0, 0, 1, 1}), "g"),
              HasSubstr("every failure lies above every survival: the median lies between 0.2 g and 0.4 g"));
  EXPECT_THAT(degenerate_reason(fit_lognormal_fragility({0.2, 0.6, 0.6, 1.0}, {0, 1, 0, 1}), "g"),
              HasSubstr("failures and survivals mix at 0.6 g only"));
  EXPECT_EQ(degenerate_reason(fit_lognormal_fragility({}, {}), "g"), "no run yet");
}

// What fragility_fit.csv says of the median, and where a curve may be drawn: not where no
// run failed or every one did (a step at the level run would claim a certainty the runs do
// not give).
TEST(Fragility, MedianIsSaysWhereAndACurveOnlyWhereRunsBothFailedAndStood) {
  const FragilityFit none_failed = fit_lognormal_fragility({0.2, 0.6}, {0, 0});
  EXPECT_STREQ(median_is(none_failed), "above");
  EXPECT_EQ(none_failed.highest_survival, 0.6);
  EXPECT_EQ(none_failed.lowest_failure, 0.0);
  EXPECT_FALSE(has_curve(none_failed));
  EXPECT_STREQ(median_is(fit_lognormal_fragility({0.2, 0.6}, {1, 1})), "below");
  EXPECT_FALSE(has_curve(fit_lognormal_fragility({0.2, 0.6}, {1, 1})));
  const FragilityFit separated = fit_lognormal_fragility({0.1, 0.2, 0.4, 0.8}, {0, 0, 1, 1});
  EXPECT_STREQ(median_is(separated), "between");
  EXPECT_TRUE(has_curve(separated));
  EXPECT_STREQ(median_is(fit_lognormal_fragility({0.2, 0.6, 0.6, 1.0}, {0, 1, 0, 1})), "at");
  const FragilityFit mixed = fit_lognormal_fragility({0.1, 0.2, 0.3, 0.4, 0.5}, {0, 1, 0, 1, 1});
  EXPECT_STREQ(median_is(mixed), "fit");
  EXPECT_TRUE(has_curve(mixed));
  EXPECT_STREQ(median_is(fit_lognormal_fragility({}, {})), "none");
}

// Outcomes at n random levels around the median of the curve (median, beta).
void draw_outcomes(std::mt19937& random, double median, double beta, int n, std::vector<double>& x, std::vector<int>& failed) {
  std::uniform_real_distribution<double> level(std::log(0.45) - 1.0, std::log(0.45) + 1.0);
  std::uniform_real_distribution<double> u(0, 1);
  x.clear();
  failed.clear();
  for (int i = 0; i < n; ++i) {
    x.push_back(std::exp(level(random)));
    failed.push_back(u(random) < 0.5 * std::erfc(-std::log(x.back() / median) / beta / std::sqrt(2.0)));
  }
}

// The p-value means what it says: drawn from one curve, about 5 % of comparisons fall
// below 0.05 (binomial spread of 400 trials: 0.05 +- 0.022 at two sigma); curves whose
// medians differ by half are told apart.
TEST(Fragility, ComparisonPValueIsCalibratedAndSeparatesDifferentCurves) {
  std::mt19937 random(11);
  std::vector<double> xa, xb;
  std::vector<int> fa, fb;
  int rejected = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    draw_outcomes(random, 0.45, 0.35, 150, xa, fa);
    draw_outcomes(random, 0.45, 0.35, 150, xb, fb);
    rejected += compare_fragilities(xa, fa, xb, fb).p_value < 0.05;
  }
  EXPECT_GT(rejected, 0.028 * trials);
  EXPECT_LT(rejected, 0.072 * trials);
  draw_outcomes(random, 0.45, 0.35, 150, xa, fa);
  draw_outcomes(random, 0.70, 0.35, 150, xb, fb);
  const FragilityComparison apart = compare_fragilities(xa, fa, xb, fb);
  EXPECT_LT(apart.p_value, 1e-3);
  EXPECT_NEAR(apart.p_value, std::exp(-0.5 * apart.statistic), 1e-15);
}

}  // namespace
}  // namespace ishibashi
