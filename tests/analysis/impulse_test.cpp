// Natural frequencies by impulse response and Fourier analysis, against closed forms and
// against the modal analysis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "analysis/dynamics/frequencies.h"
#include "analysis/dynamics/impulse.h"
#include "analysis/dynamics/modal.h"
#include "analysis/dynamics/spectrum.h"
#include "engine/world.h"
#include "geometry/bridge.h"
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

TEST(Spectrum, EveryPeakOfTwoSinesAndNoneOfTheWindowsSidelobes) {
  const double dt = 0.005;
  std::vector<double> x;
  for (int i = 0; i < 4000; ++i) x.push_back(std::sin(2 * kPi * 3.1 * i * dt) + 0.3 * std::sin(2 * kPi * 11.7 * i * dt));
  const std::vector<SpectralPeak> peaks = spectral_peaks(amplitude_spectrum(x, dt));
  ASSERT_EQ(peaks.size(), 2u);
  EXPECT_NEAR(peaks[0].frequency_hz, 3.1, 0.01);
  EXPECT_NEAR(peaks[1].frequency_hz, 11.7, 0.02);
  EXPECT_NEAR(peaks[1].relative_amplitude, 0.3, 0.03);
}

// A sine of amplitude A reads A at its peak (the window's gain divided out), its frequency
// found between the bins to a tenth of one by the parabola, and about an
// offset ten times its amplitude (a block that settles while it rings) all the same.
TEST(Spectrum, ASinesPeakHasItsAmplitudeAndItsFrequencyBetweenTheBins) {
  const double dt = 0.01, amplitude = 2.5e-4;  // s, m
  for (const double offset : {0.0, 10 * amplitude})
    for (const double bins : {40.0, 40.25, 40.5}) {
      const int n = 1000;
      const double f = bins / (4096 * dt);  // 1000 samples padded to 4096: the bin is 1 / (4096 dt)
      std::vector<double> x;
      for (int i = 0; i < n; ++i) x.push_back(offset + amplitude * std::sin(2 * kPi * f * i * dt + 0.7));
      const Spectrum s = amplitude_spectrum(x, dt);
      SCOPED_TRACE("offset " + std::to_string(offset) + " m, " + std::to_string(bins) + " bins");
      const std::vector<SpectralPeak> peaks = spectral_peaks(s);
      ASSERT_EQ(peaks.size(), 1u);
      EXPECT_NEAR(peaks[0].frequency_hz, f, 0.1 * s.resolution_hz());
      EXPECT_EQ(peaks[0].relative_amplitude, 1.0);
      const double top = *std::max_element(s.amplitude.begin(), s.amplitude.end());
      // Between two bins the Hann window's peak loses up to 15 % (its scalloping).
      EXPECT_NEAR(top, amplitude, (bins == 40.0 ? 0.01 : 0.16) * amplitude);
    }
}

TEST(Impulse, BlockOnBaseFrequenciesMatchClosedFormsAndModes) {
  const double h = 0.64, a = h / 2, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(h * h, a, a, kE), ks = kn / (2 * (1 + kNu));
  const Model m = test::block_on_base(Vec3(h, h, h), test::stone(1.0)).build({.linear_joints = true});
  const double vertical = std::sqrt(kn / mass) / (2 * kPi);
  Eigen::Matrix2d k, mm;
  k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * a * a;
  mm << mass, 0, 0, inertia;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
  const double rocking = std::sqrt(sway.eigenvalues()[0]) / (2 * kPi);  // lower sway-rocking mode

  const ImpulseResponse z = impulse_response(m, 2, 1, 0.1);
  const ImpulseResponse x = impulse_response(m, 0, 1, 0.1);
  const double fz = first_peak_hz(amplitude_spectrum(z.displacement_m[2], z.dt_s));
  const double fx = first_peak_hz(amplitude_spectrum(x.displacement_m[0], x.dt_s));
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

// An x step excites both coupled sway-rocking modes of a block on a base (a 2 x 2
// eigenproblem in sway and rocking); read in y, the symmetric block does not move.
TEST(Impulse, BothSwayRockingModesAndNoResponseAcrossTheSymmetryPlane) {
  const double h = 0.64, a = h / 2, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(h * h, a, a, kE), ks = kn / (2 * (1 + kNu));
  const Model m = test::block_on_base(Vec3(h, h, h), test::stone(1.0)).build({.linear_joints = true});
  Eigen::Matrix2d k, mm;
  k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * a * a;
  mm << mass, 0, 0, inertia;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
  const ImpulseResponse x = impulse_response(m, 0, 1, 0.1, 0.0, 1e-4, 2e-4);  // a short rise excites both
  const std::vector<SpectralPeak> peaks = spectral_peaks(amplitude_spectrum(x.displacement_m[0], x.dt_s), 0.01);
  ASSERT_GE(peaks.size(), 2u);
  for (int mode = 0; mode < 2; ++mode) {
    const double f = std::sqrt(sway.eigenvalues()[mode]) / (2 * kPi);
    double nearest = peaks.front().frequency_hz;
    for (const SpectralPeak& p : peaks)
      if (std::abs(p.frequency_hz - f) < std::abs(nearest - f)) nearest = p.frequency_hz;
    EXPECT_NEAR(nearest, f, 0.02 * f) << "mode " << mode;
  }
  double largest_x = 0, largest_y = 0;  // the x step read in x and across the symmetry plane, in y
  for (double d : x.displacement_m[0]) largest_x = std::max(largest_x, std::abs(d));
  for (double d : x.displacement_m[1]) largest_y = std::max(largest_y, std::abs(d));
  EXPECT_LT(largest_y, 1e-9 * largest_x + 1e-15);
}


// Model A's ring: its crown unit lies on both symmetry planes, so an x step (the
// antisymmetric in-plane mode) barely moves it vertically; the face unit beside it is off
// both planes and shows that mode vertically, the first clear peak of its z response at the
// first x mode of the modal analysis.
TEST(Impulse, FaceUnitBesideTheCrownShowsTheInPlaneModeVertically) {
  const LoadedModel a = load_model_or_scenario(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / "nishida_a.toml");
  const Model& m = a.model();
  const int crown = crown_unit(m), face = face_unit_beside_crown(m);
  ASSERT_GE(face, 0);
  const Vec3 c = m.initial_position[crown], f = m.initial_position[face];
  EXPECT_NEAR(c.x(), 0, 1e-6);
  EXPECT_NEAR(c.y(), 0, 1e-6);
  EXPECT_GT(f.x(), 0.3);                    // the next voussoir along the ring
  EXPECT_NEAR(f.y(), 1.6 - 0.32, 1e-6);     // the face course of the 3.2 m wide ring

  const FrequencyAnalysis r = analyse_frequencies(
      a, {.modes = 4, .impulse_s = 0.3, .impulses = {{0, 0, ImpulseSpec::kFaceUnitBesideCrown}, {0, 2, ImpulseSpec::kFaceUnitBesideCrown},
                                                     {0, 2, ImpulseSpec::kCrownUnit}}},
      std::filesystem::temp_directory_path() / "ishibashi_face_unit_test");
  std::filesystem::remove_all(std::filesystem::temp_directory_path() / "ishibashi_face_unit_test");
  ASSERT_EQ(r.impulses.size(), 3u);
  auto largest = [](const Spectrum& s) { return *std::max_element(s.amplitude.begin(), s.amplitude.end()); };
  const double own = largest(r.impulses[0].spectrum);
  EXPECT_GT(largest(r.impulses[1].spectrum), 0.1 * own);   // the face unit moves vertically
  EXPECT_LT(largest(r.impulses[2].spectrum), 0.01 * own);  // the crown unit does not
  EXPECT_NEAR(first_peak_hz(r.impulses[1].spectrum), r.first_mode_hz[0], 0.01 * r.first_mode_hz[0]);
}

}  // namespace
}  // namespace ishibashi
