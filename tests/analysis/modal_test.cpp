// Modal analysis against closed forms of blocks on joint springs.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "analysis/dynamics/modal.h"
#include "analysis/dynamics/modal_energy.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846, kRho = 1.88e3, kE = 1.4039e10, kNu = 0.28;

// The block on its base with either shear spring: K_s from G, or K_s = K_n.
void expect_block_on_base_closed_forms(ShearSpring spring) {
  // A 0.64 m cube on a fixed base 0.64 m thick: joint springs K_n = S / (l/E + l/E) and
  // K_s likewise with G, four corner sub-contacts (K_n / 4 each at x, y = +-a).
  const double h = 0.64, a = h / 2, area = h * h, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(area, a, a, kE), ks = spring == ShearSpring::normal ? kn : kn / (2 * (1 + kNu));
  ModelBuilder b = test::block_on_base(Vec3(h, h, h), test::stone(0.0));
  b.set_gravity(Vec3::Zero());
  World w(b.build({.shear_spring = spring}), 1e-6);
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

TEST(Modal, BlockOnBaseMatchesSpringClosedForms) { expect_block_on_base_closed_forms(ShearSpring::shear_modulus); }

TEST(Modal, BlockOnBaseMatchesSpringClosedFormsWithTheShearSpringAsStiffAsTheNormal) {
  expect_block_on_base_closed_forms(ShearSpring::normal);
}

// The same cube with each joint rule against the closed form of that rule's second moment:
// the corner rule rocks on K_n a^2 (four corners at x, y = +-a), the moment rule on the
// uniform bed's K_n (2a)^2 / 12 = K_n a^2 / 3; twist likewise with K_s and the polar moment.
TEST(Modal, BlockOnBaseFrequenciesFollowEachJointRulesSecondMoment) {
  const double h = 0.64, a = h / 2, area = h * h, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(area, a, a, kE), ks = kn / (2 * (1 + kNu));
  for (const auto& [rule, second_moment] : {std::pair{JointRule::corners, a * a}, std::pair{JointRule::moments, a * a / 3}}) {
    ModelBuilder b = test::block_on_base(Vec3(h, h, h), test::stone(0.0));
    b.set_gravity(Vec3::Zero());
    World w(b.build({.joint_rule = rule}), 1e-6);
    EXPECT_EQ(sub_contact_count(w.state()), rule == JointRule::corners ? 4 : 9);
    const ModalResult r = modal_analysis(w.model(), w.state(), 6);
    const double vertical = std::sqrt(kn / mass) / (2 * kPi);
    const double torsion = std::sqrt(ks * 2 * second_moment / inertia) / (2 * kPi);
    Eigen::Matrix2d k, mm;
    k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * second_moment;
    mm << mass, 0, 0, inertia;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
    std::vector<double> expected{vertical, torsion, std::sqrt(sway.eigenvalues()[0]) / (2 * kPi),
                                 std::sqrt(sway.eigenvalues()[1]) / (2 * kPi)};
    for (double f : expected) {
      double nearest = 0;
      for (double g : r.frequency_hz)
        if (std::abs(g - f) < std::abs(nearest - f)) nearest = g;
      EXPECT_NEAR(nearest, f, 0.01 * f) << joint_rule_name(rule);
    }
  }
}

// Two free cubes in zero gravity, touching nothing, joined by a rod along the line of their
// centroids: one mode of the rod, omega^2 = k / (m / 2) with k = E A / L; the other eleven are
// rigid-body modes (0 Hz), the rod having no lever about either centroid.
TEST(Modal, TwoStonesOnATieRodSwingAtTheRodsFrequency) {
  ModelBuilder b;
  b.set_gravity(Vec3::Zero());
  const int mat = b.add_material(test::stone(0.0));
  for (double x : {-1.5, 1.5}) {
    const Polyhedron cube = make_box(Vec3(x, 0, 0), Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat);
  }
  const double area = 1e-3, young = 2e11, k = young * area / 2.4;
  b.add_tie(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0), area, young, 2.35e8);
  World w(b.build(), 1e-5);
  const ModalResult r = modal_analysis(w.model(), w.state(), 12);
  ASSERT_EQ(r.frequency_hz.size(), 12u);
  const double expected = std::sqrt(k / (0.5 * kRho)) / (2 * kPi);  // each cube 1 m^3
  EXPECT_NEAR(r.frequency_hz.back(), expected, 1e-6 * expected);
  EXPECT_LT(r.frequency_hz[10], 1e-3 * expected);
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


// The strain energy of a mode by joint, against the two-block chain's eigenvectors: in the
// first vertical mode (x2 = x1 (1 + sqrt 5) / 2) the base joint holds k x1^2 and the joint
// between the blocks k (x2 - x1)^2, so 1 / (1 + ((sqrt 5 - 1) / 2)^2) = 72.4 % sits in the
// base joint; in the second (x2 = -x1 (sqrt 5 - 1) / 2), 27.6 %. All of it in normal springs.
TEST(Modal, EnergySharesOfTheTwoBlockChainFollowItsEigenvectors) {
  const double h = 0.64;
  ModelBuilder b;
  const int mat = b.add_material(test::stone(0.0));
  const Polyhedron base = make_box(Vec3(0, 0, -0.5 * h), Vec3(4, 4, h)), low = make_box(Vec3(0, 0, 0.5 * h), Vec3(h, h, h)),
                   high = make_box(Vec3(0, 0, 1.5 * h), Vec3(h, h, h));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base", BlockTag{static_cast<int>(Part::ground), 0});
  b.add_block(low.vertices, low.faces, mat, Motion::free, "low", BlockTag{static_cast<int>(Part::wall), 0});
  b.add_block(high.vertices, high.faces, mat, Motion::free, "high", BlockTag{static_cast<int>(Part::fill), 1});
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 1e-6);
  const ModalResult r = modal_analysis(w.model(), w.state(), 12);
  const double golden = (std::sqrt(5.0) - 1) / 2, first = 1 / (1 + golden * golden);
  std::vector<double> expected_base_share{first, 1 - first};
  for (std::size_t i = 0; i < r.frequency_hz.size(); ++i) {
    if (r.effective_mass_ratio[i].z() < 0.01) continue;
    ASSERT_FALSE(expected_base_share.empty());
    const std::vector<JointEnergyShare> shares = modal_energy_shares(w.model(), w.state(), r, static_cast<int>(i));
    ASSERT_EQ(shares.size(), 2u);
    double base = 0, total = 0;
    for (const JointEnergyShare& s : shares) {
      EXPECT_NEAR(s.shear, 0, 1e-9);
      total += s.normal;
      if (s.joint == "ground / wall") base = s.normal;
      else EXPECT_EQ(s.joint, "fill / wall");
    }
    EXPECT_NEAR(total, 1, 1e-12);
    EXPECT_NEAR(base, expected_base_share.front(), 1e-6);
    expected_base_share.erase(expected_base_share.begin());
  }
  EXPECT_TRUE(expected_base_share.empty());
}

// Sway and rocking of a block on its base: the eigenvector (u, t) of the 2x2 closed form
// puts K_n a^2 t^2 in the normal springs and K_s (u - t h / 2)^2 in the shear springs.
TEST(Modal, EnergySharesOfSwayAndRockingSplitAsTheClosedForm) {
  const double h = 0.64, a = h / 2, mass = kRho * h * h * h, inertia = mass * h * h / 6;
  const double kn = test::joint_normal_stiffness(h * h, a, a, kE), ks = kn / (2 * (1 + kNu));
  ModelBuilder b = test::block_on_base(Vec3(h, h, h), test::stone(0.0));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 1e-6);
  const ModalResult r = modal_analysis(w.model(), w.state(), 6);
  Eigen::Matrix2d k, mm;
  k << ks, -ks * h / 2, -ks * h / 2, ks * h * h / 4 + kn * a * a;
  mm << mass, 0, 0, inertia;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> sway(k, mm);
  int checked = 0;
  for (int m = 0; m < 2; ++m) {
    const double u = sway.eigenvectors()(0, m), t = sway.eigenvectors()(1, m);
    const double normal = kn * a * a * t * t, shear = ks * (u - t * h / 2) * (u - t * h / 2);
    const double f = std::sqrt(sway.eigenvalues()[m]) / (2 * kPi);
    for (std::size_t i = 0; i < r.frequency_hz.size(); ++i)
      if (std::abs(r.frequency_hz[i] - f) < 1e-3 * f) {
        const std::vector<JointEnergyShare> shares = modal_energy_shares(w.model(), w.state(), r, static_cast<int>(i));
        ASSERT_EQ(shares.size(), 1u);
        EXPECT_NEAR(shares[0].normal, normal / (normal + shear), 1e-6) << f << " Hz";
        EXPECT_NEAR(shares[0].shear, shear / (normal + shear), 1e-6) << f << " Hz";
        ++checked;
      }
  }
  EXPECT_EQ(checked, 4);  // each sway-rocking pair in x and in y
}

}  // namespace
}  // namespace ishibashi

namespace ishibashi {
namespace {

// First bending frequency of a column of `n` bonded blocks (b x b x h) on a fixed base,
// with joints subdivided `level` times.
double column_frequency(int n, int level, double b, double h, JointRule rule = JointRule::corners) {
  ModelBuilder builder;
  Material m = test::stone(0.0, 33.23, 1e9);
  const int mat = builder.add_material(m);
  const Polyhedron base = make_box(Vec3(0, 0, -h / 2), Vec3(4 * b, 4 * b, h));
  builder.add_block(base.vertices, base.faces, mat, Motion::fixed);
  for (int k = 0; k < n; ++k) {
    const Polyhedron p = make_box(Vec3(0, 0, (k + 0.5) * h), Vec3(b, b, h));
    builder.add_block(p.vertices, p.faces, mat);
  }
  builder.set_gravity(Vec3::Zero());
  World w(builder.build({.subdivision = level, .joint_rule = rule}), 1e-7);
  const ModalResult r = modal_analysis(w.model(), w.state(), 4);
  for (std::size_t i = 0; i < r.frequency_hz.size(); ++i)
    if (r.dominant_direction(static_cast<int>(i)) != 2 && r.effective_mass_ratio[i].head<2>().sum() > 0.3) return r.frequency_hz[i];
  return 0;
}

TEST(Modal, SlenderColumnApproachesEulerBernoulliAsJointsAreSubdivided) {
  // Cantilever of length L: f = 1.875^2 / (2 pi) sqrt(E I / (rho A L^4)). Each joint's
  // springs are those of a block length of material, so a uniform spring bed gives the
  // beam's bending stiffness; corner points (subdivision 1) are 3 times too stiff in
  // rotation. What remains is the chain of rigid blocks, an error of order h / L: about
  // 2.5 % for 40 blocks (4.9 % for 20, 9 % for 10, measured).
  const int n = 40;
  const double b = 0.2, length = 8.0, h = length / n;
  const double area = b * b, second_moment = b * b * b * b / 12;
  const double euler = 1.875 * 1.875 / (2 * kPi) * std::sqrt(kE * second_moment / (kRho * area * std::pow(length, 4)));
  double last_error = 1e9;
  for (int level : {1, 3, 8}) {
    const double f = column_frequency(n, level, b, h);
    const double error = std::abs(f / euler - 1);
    EXPECT_LT(error, last_error) << "subdivision " << level << ": " << f << " Hz vs " << euler;
    last_error = error;
  }
  EXPECT_LT(last_error, 0.03);
}

// The same column as a chain of rigid blocks, built by hand: per block the sway u and the
// rotation t about y; each joint a shear spring K_s on the relative sway of its two faces
// (u - t h/2 above, u + t h/2 below) and a rotational spring K_n r^2, r^2 = a^2 for the
// corner rule (four corners at +-a) and a^2 / 3 for the moment rule (a uniform bed).
// Its first bending frequency against the engine's modal analysis of the column, within 2 %.
double chain_frequency(int n, double b, double h, double r2) {
  const double area = b * b, kn = area * kE / h, ks = kn / (2 * (1 + kNu)), kr = kn * r2;
  const double mass = kRho * area * h, inertia = mass * (b * b + h * h) / 12;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n), mm = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int j = 0; j < n; ++j) {  // joint j: below block j (the base for j = 0)
    Eigen::VectorXd shear = Eigen::VectorXd::Zero(2 * n), turn = Eigen::VectorXd::Zero(2 * n);
    shear(2 * j) = 1, shear(2 * j + 1) = -h / 2, turn(2 * j + 1) = 1;
    if (j > 0) shear(2 * j - 2) = -1, shear(2 * j - 1) = -h / 2, turn(2 * j - 1) = -1;
    k += ks * shear * shear.transpose() + kr * turn * turn.transpose();
    mm(2 * j, 2 * j) = mass, mm(2 * j + 1, 2 * j + 1) = inertia;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> chain(k, mm);
  return std::sqrt(chain.eigenvalues()[0]) / (2 * kPi);
}

TEST(Modal, ColumnOfBondedBlocksMatchesTheRigidChainForEachJointRule) {
  const int n = 10;
  const double b = 0.3, h = 0.3;
  for (const auto& [rule, r2] : {std::pair{JointRule::corners, b * b / 4}, std::pair{JointRule::moments, b * b / 12}}) {
    const double expected = chain_frequency(n, b, h, r2);
    EXPECT_NEAR(column_frequency(n, 1, b, h, rule), expected, 0.02 * expected) << joint_rule_name(rule);
  }
}

}  // namespace
}  // namespace ishibashi
