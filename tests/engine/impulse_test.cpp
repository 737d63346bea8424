// Natural frequencies by impulse response and Fourier analysis, against closed forms and
// against the modal analysis.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/impulse.h"
#include "engine/modal.h"
#include "engine/spectrum.h"
#include "engine/world.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846, kRho = 1.88e3, kE = 1.4039e10, kNu = 0.28;

TEST(Spectrum, PeakOfADampedSineWithinTheResolution) {
  const double f = 7.3, dt = 0.01;
  std::vector<double> x;
  for (int i = 0; i < 1000; ++i) x.push_back(std::exp(-0.3 * i * dt) * std::sin(2 * kPi * f * i * dt) + 0.2);
  const Spectrum s = amplitude_spectrum(x, dt);
  EXPECT_NEAR(first_peak_hz(s), f, s.resolution_hz());
  EXPECT_NEAR(first_peak_hz(s), f, 0.01 * f);  // the parabola does better than a bin
}

TEST(Impulse, BlockOnBaseFrequenciesMatchClosedFormsAndModes) {
  const double h = 0.64, a = h / 2, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(h * h, a, a, kE), ks = kn / (2 * (1 + kNu));
  const Model m = linear_joint_model(test::block_on_base(Vec3(h, h, h), test::stone(1.0)).build());
  const double vertical = std::sqrt(kn / mass) / (2 * kPi);
  Eigen::Matrix2d k, mm;
  k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * a * a;
  mm << mass, 0, 0, inertia;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
  const double rocking = std::sqrt(sway.eigenvalues()[0]) / (2 * kPi);  // lower sway-rocking mode

  const ImpulseResponse z = impulse_response(m, 2, 1, 0.1);
  const ImpulseResponse x = impulse_response(m, 0, 1, 0.1);
  const double fz = first_peak_hz(amplitude_spectrum(z.displacement_m, z.dt_s));
  const double fx = first_peak_hz(amplitude_spectrum(x.displacement_m, x.dt_s));
  EXPECT_NEAR(fz, vertical, 0.01 * vertical);
  EXPECT_NEAR(fx, rocking, 0.01 * rocking);

  // The modes with the largest effective mass in x and z agree with the impulse peaks.
  World w(m, 1e-6);
  const ModalResult r = modal_analysis(m, w.state(), 6);
  for (int axis : {0, 2}) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < r.frequency_hz.size(); ++i)
      if (r.effective_mass_ratio[i][axis] > r.effective_mass_ratio[best][axis]) best = i;
    const double peak = axis == 0 ? fx : fz;
    EXPECT_NEAR(r.frequency_hz[best], peak, 0.03 * peak) << "axis " << axis;
  }
}

}  // namespace
}  // namespace ishibashi
