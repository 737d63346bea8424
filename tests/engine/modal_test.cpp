// Modal analysis against closed forms of blocks on joint springs.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/modal.h"
#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846, kRho = 1.88e3, kE = 1.4039e10, kNu = 0.28;

TEST(Modal, BlockOnBaseMatchesSpringClosedForms) {
  // A 0.64 m cube on a fixed base 0.64 m thick: joint springs K_n = S / (l/E + l/E) and
  // K_s likewise with G, four corner sub-contacts (K_n / 4 each at x, y = +-a).
  const double h = 0.64, a = h / 2, area = h * h, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(area, a, a, kE), ks = kn / (2 * (1 + kNu));
  ModelBuilder b = test::block_on_base(Vec3(h, h, h), test::stone(0.0));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 1e-6);
  const ModalResult r = modal_analysis(w.model(), w.state(), 6);
  ASSERT_EQ(r.frequency_hz.size(), 6u);

  // Vertical: omega^2 = K_n / m. Torsion about z: K_s * sum(x^2 + y^2) / 4 * 4 / I_z.
  const double vertical = std::sqrt(kn / mass) / (2 * kPi);
  const double torsion = std::sqrt(ks * 2 * a * a / inertia) / (2 * kPi);
  // Sway (u along x) coupled with rocking (theta about y): the shear spring acts at the
  // joint, h/2 below the centroid; the corners resist rocking with K_n a^2.
  Eigen::Matrix2d k, mm;
  k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * a * a;
  mm << mass, 0, 0, inertia;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
  const double f1 = std::sqrt(sway.eigenvalues()[0]) / (2 * kPi), f2 = std::sqrt(sway.eigenvalues()[1]) / (2 * kPi);

  auto near = [&](double f) {
    for (double g : r.frequency_hz)
      if (std::abs(g - f) < 0.01 * f) return true;
    return false;
  };
  EXPECT_TRUE(near(vertical)) << vertical;
  EXPECT_TRUE(near(torsion)) << torsion;
  EXPECT_TRUE(near(f1)) << f1;  // x and y each: a pair of equal frequencies
  EXPECT_TRUE(near(f2)) << f2;
  // The vertical mode carries the whole mass in z.
  for (std::size_t i = 0; i < r.frequency_hz.size(); ++i)
    if (std::abs(r.frequency_hz[i] - vertical) < 0.01 * vertical) {
      EXPECT_NEAR(r.effective_mass_ratio[i].z(), 1.0, 1e-6);
      EXPECT_EQ(r.dominant_direction(static_cast<int>(i)), 2);
    }
}

TEST(Modal, TwoStackedBlocksMatchTheTwoDofClosedForm) {
  // Vertical modes of two equal blocks: K = k [[2, -1], [-1, 1]], M = m I gives
  // omega^2 = k / m (3 -+ sqrt 5) / 2.
  const double h = 0.64, mass = kRho * h * h * h;
  ModelBuilder b = test::block_on_base(Vec3(h, h, h), test::stone(0.0), h);
  const Polyhedron top = make_box(Vec3(0, 0, 1.5 * h), Vec3(h, h, h));
  b.add_block(top.vertices, top.faces, 0, Motion::free, "top");
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 1e-6);
  const double k = test::joint_normal_stiffness(h * h, h / 2, h / 2, kE);
  const ModalResult r = modal_analysis(w.model(), w.state(), 12);
  std::vector<double> vertical;
  for (std::size_t i = 0; i < r.frequency_hz.size(); ++i)
    if (r.dominant_direction(static_cast<int>(i)) == 2 && r.effective_mass_ratio[i].z() > 0.01) vertical.push_back(r.frequency_hz[i]);
  ASSERT_EQ(vertical.size(), 2u);
  EXPECT_NEAR(vertical[0], std::sqrt(k / mass * (3 - std::sqrt(5.0)) / 2) / (2 * kPi), 1e-3 * vertical[0]);
  EXPECT_NEAR(vertical[1], std::sqrt(k / mass * (3 + std::sqrt(5.0)) / 2) / (2 * kPi), 1e-3 * vertical[1]);
}

}  // namespace
}  // namespace ishibashi
