#include "analysis/batch/fragility.h"

#include <cstdio>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ishibashi {
namespace {

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double normal_pdf(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI); }

// Log-likelihood of probit outcomes with z_i = a + b ln x_i; gradient and Hessian in (a, b).
double log_likelihood(const std::vector<double>& lnx, const std::vector<int>& y, double a, double b, Eigen::Vector2d* grad,
                      Eigen::Matrix2d* hess) {
  double l = 0;
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  for (std::size_t i = 0; i < lnx.size(); ++i) {
    const double z = a + b * lnx[i];
    // y = 1: ln Phi(z); y = 0: ln Phi(-z). With s = +-1, ln Phi(s z); d/dz = s lambda,
    // d2/dz2 = -lambda (lambda + s z), lambda = phi(z) / Phi(s z).
    const double s = y[i] ? 1.0 : -1.0;
    const double p = std::max(normal_cdf(s * z), 1e-300);
    l += std::log(p);
    const double lambda = normal_pdf(z) / p;
    const double d1 = s * lambda, d2 = -lambda * (lambda + s * z);
    const Eigen::Vector2d dz(1.0, lnx[i]);
    if (grad) *grad += d1 * dz;
    if (hess) *hess += d2 * dz * dz.transpose();
  }
  return l;
}

}  // namespace

FragilityFit fit_lognormal_fragility(const std::vector<double>& intensity, const std::vector<int>& failed) {
  FragilityFit fit;
  fit.outcomes = static_cast<int>(intensity.size());
  if (intensity.empty()) {  // a variant of a sweep stopped before its first run
    fit.degenerate = true;
    return fit;
  }
  std::vector<double> lnx;
  double mean = 0;
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    lnx.push_back(std::log(intensity[i]));
    mean += lnx.back() / intensity.size();
    fit.failures += failed[i] != 0;
  }
  double highest_survival = -std::numeric_limits<double>::infinity(), lowest_failure = -highest_survival;
  for (std::size_t i = 0; i < lnx.size(); ++i) {
    if (failed[i]) lowest_failure = std::min(lowest_failure, lnx[i]);
    else highest_survival = std::max(highest_survival, lnx[i]);
  }
  fit.highest_survival = std::isfinite(highest_survival) ? std::exp(highest_survival) : 0.0;
  fit.lowest_failure = std::isfinite(lowest_failure) ? std::exp(lowest_failure) : 0.0;
  // One level: the same intensity within rounding (a sweep scales each record to a level,
  // so records at one level differ in their last bits).
  constexpr double kSameLevel = 1e-9;  // in ln x
  if (fit.failures == 0 || fit.failures == fit.outcomes || lowest_failure > highest_survival - kSameLevel) {
    // No finite maximum: the median lies between the highest survival and the lowest failure
    // (beta -> 0). When they are one level (outcomes mixed there only, as an ensemble's
    // members at one intensity are), the median is that level and the likelihood's
    // supremum that of its own failure share, p^f (1 - p)^s; Newton's method would stop
    // at whatever small beta its iterations reached.
    fit.degenerate = true;
    const double lo = std::isfinite(highest_survival) ? highest_survival : lowest_failure;
    const double hi = std::isfinite(lowest_failure) ? lowest_failure : highest_survival;
    fit.median = std::exp(0.5 * (lo + hi));
    fit.beta = 0;
    if (std::abs(lowest_failure - highest_survival) <= kSameLevel) {
      int at_failed = 0, at_stood = 0;
      for (std::size_t i = 0; i < lnx.size(); ++i) {
        if (failed[i]) at_failed += lnx[i] <= highest_survival + kSameLevel;
        else at_stood += lnx[i] >= lowest_failure - kSameLevel;
      }
      const double p = static_cast<double>(at_failed) / (at_failed + at_stood);
      fit.log_likelihood = at_failed * std::log(p) + at_stood * std::log(1.0 - p);
    }
    return fit;
  }
  // Newton's method from beta = 0.5 at the mean intensity, halving steps that do not
  // raise the likelihood (it is concave in (a, b), so this converges).
  double b = 2.0, a = -b * mean;
  Eigen::Vector2d grad;
  Eigen::Matrix2d hess;
  double l = log_likelihood(lnx, failed, a, b, &grad, &hess);
  for (int iteration = 0; iteration < 100 && grad.norm() > 1e-10 * fit.outcomes; ++iteration) {
    const Eigen::Vector2d step = hess.ldlt().solve(-grad);
    double t = 1.0;
    for (int halving = 0; halving < 40; ++halving, t *= 0.5) {
      const double trial = log_likelihood(lnx, failed, a + t * step[0], b + t * step[1], nullptr, nullptr);
      if (trial >= l) break;
    }
    a += t * step[0];
    b += t * step[1];
    l = log_likelihood(lnx, failed, a, b, &grad, &hess);
  }
  fit.log_likelihood = l;
  fit.median = std::exp(-a / b);
  fit.beta = 1.0 / b;
  fit.degenerate = !(b > 0);
  return fit;
}

const char* median_is(const FragilityFit& fit) {
  if (!fit.degenerate) return "fit";
  if (fit.outcomes == 0) return "none";
  if (fit.failures == 0) return "above";
  if (fit.failures == fit.outcomes) return "below";
  // Separated: all failures above all survivals, apart, or mixed at one level only.
  return fit.lowest_failure <= fit.highest_survival * (1 + 1e-9) ? "at" : "between";
}

bool has_curve(const FragilityFit& fit) { return fit.failures > 0 && fit.failures < fit.outcomes; }

std::string degenerate_reason(const FragilityFit& fit, const std::string& unit) {
  auto x = [&](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g %s", v, unit.c_str());
    return std::string(text);
  };
  const std::string kind = median_is(fit);
  if (kind == "fit") return "";
  if (kind == "none") return "no run yet";
  if (kind == "above") return "no run failed: the median lies above " + x(fit.highest_survival) + ", the highest level run";
  if (kind == "below") return "every run failed: the median lies below " + x(fit.lowest_failure) + ", the lowest level run";
  if (kind == "at")
    return "failures and survivals mix at " + x(fit.median) + " only, apart elsewhere: the median is that level, the "
           "dispersion unknown";
  return "every failure lies above every survival: the median lies between " + x(fit.highest_survival) + " and " +
         x(fit.lowest_failure) + " (the curve drawn at their geometric mean), the dispersion unknown";
}

double failure_probability(const FragilityFit& fit, double intensity) {
  if (fit.beta <= 0) return intensity >= fit.median ? 1.0 : 0.0;
  return normal_cdf(std::log(intensity / fit.median) / fit.beta);
}

FragilityComparison compare_fragilities(const std::vector<double>& intensity_a, const std::vector<int>& failed_a,
                                        const std::vector<double>& intensity_b, const std::vector<int>& failed_b) {
  std::vector<double> intensity = intensity_a;
  std::vector<int> failed = failed_a;
  intensity.insert(intensity.end(), intensity_b.begin(), intensity_b.end());
  failed.insert(failed.end(), failed_b.begin(), failed_b.end());
  FragilityComparison c;
  c.statistic = std::max(0.0, 2.0 * (fit_lognormal_fragility(intensity_a, failed_a).log_likelihood +
                                     fit_lognormal_fragility(intensity_b, failed_b).log_likelihood -
                                     fit_lognormal_fragility(intensity, failed).log_likelihood));
  c.p_value = std::exp(-0.5 * c.statistic);
  return c;
}

}  // namespace ishibashi
