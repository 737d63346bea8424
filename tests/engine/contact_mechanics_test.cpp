// Contact mechanics against closed forms: a block resting on a base, sliding (and each
// sub-contact's slip) and tipping on an incline, the shear spring turned with its joint and
// released as a dry joint opens, the vertical natural frequency, bonded joint strength and
// how much of it a held load uses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/joints.h"
#include "engine/pipeline.h"
#include "engine/world.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kG = 9.81;
constexpr double kRho = 1.88e3, kE = 1.4039e10;
constexpr double kPi = 3.14159265358979323846;

double deg(double d) { return d * kPi / 180.0; }

// Total force of sub-contact i on block b (springs + dashpots) of the last contact law, N.
Vec3 force_on_b(const SubContacts& c, std::size_t i) {
  return c.shear_spring(i) - c.normal_spring(i) * c.normal[i] + c.damping_force_n[i];
}

// Gravity tilted by theta about y: the same as a base tilted by theta (slope down +x).
Vec3 tilted_gravity(double theta) { return kG * Vec3(std::sin(theta), 0, -std::cos(theta)); }

TEST(Resting, CubeOnBaseCarriesItsWeightEquallyAndSettlesByMgOverKn) {
  const double a = 0.64;
  World w(test::block_on_base(Vec3(a, a, a), test::stone()).build(), 4e-5);
  w.run(5000);  // 0.2 s, about 130 periods of the (critically damped) joint
  const State& s = w.state();
  const double mg = kRho * a * a * a * kG;
  const double kn = test::joint_normal_stiffness(a * a, a / 2, a / 2, kE);
  ASSERT_EQ(s.contacts.size(), 4u);
  double total = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    total += force_on_b(s.contacts, i).z();
    EXPECT_NEAR(force_on_b(s.contacts, i).z(), mg / 4, 1e-3 * mg / 4) << "corner " << i;
  }
  EXPECT_NEAR(total, mg, 1e-3 * mg);
  const double settlement = a / 2 - s.position[1].z();
  EXPECT_NEAR(settlement, mg / kn, 1e-3 * mg / kn);
}

double slide_acceleration(double theta, double friction_deg, double* drift_at_rest) {
  const double a = 0.64;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, friction_deg));
  b.set_gravity(tilted_gravity(theta));
  World w(b.build(), 4e-5);
  w.run(5000);  // 0.2 s
  const double x1 = w.state().position[1].x(), v1 = w.state().velocity[1].x(), t1 = w.state().time_s;
  w.run(5000);
  const double v2 = w.state().velocity[1].x(), t2 = w.state().time_s;
  if (drift_at_rest) *drift_at_rest = std::abs(w.state().position[1].x() - x1);
  return (v2 - v1) / (t2 - t1);
}

TEST(Incline, BlockStaysWhenTanThetaBelowTanPhi) {
  double drift = 0;
  const double acc = slide_acceleration(deg(30.0), 33.23, &drift);
  EXPECT_LT(std::abs(acc), 1e-6);
  EXPECT_LT(drift, 1e-9);  // no creep over 0.2 s
}

TEST(Incline, BlockSlidesWithClosedFormAcceleration) {
  for (double theta_deg : {36.0, 40.0}) {
    const double theta = deg(theta_deg), phi = deg(33.23);
    const double expected = kG * (std::sin(theta) - std::cos(theta) * std::tan(phi));
    const double acc = slide_acceleration(theta, 33.23, nullptr);
    EXPECT_NEAR(acc, expected, 0.01 * expected) << "theta " << theta_deg;
  }
}

// A sub-contact's tangential travel is its shear spring's stretch plus its accumulated slip
// (the plastic part): for a block sliding without turning, the block's own travel.
TEST(Incline, EachSubContactSlipsAsFarAsTheBlockSlidesLessItsSpringsStretch) {
  const double a = 0.64;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, 33.23));
  b.set_gravity(tilted_gravity(deg(40.0)));
  World w(b.build(), 4e-5);
  const double x0 = w.state().position[1].x();
  w.run(10000);  // 0.4 s: about 0.1 m down the slope
  const State& s = w.state();
  const double travel = s.position[1].x() - x0;
  ASSERT_GT(travel, 0.05);
  ASSERT_EQ(s.contacts.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GT(s.contacts.slip_m[i], 0.9 * travel) << "sub-contact " << i;
    EXPECT_NEAR(s.contacts.slip_m[i] + s.contacts.shear_stretch_m[i].norm(), travel, 1e-3 * travel) << "sub-contact " << i;
  }
}

// A 0.64 m cube on a base without gravity, after one step: its joint's four sub-contacts,
// at rest, for the law to be called on by hand (apply_contact_law). bond_pa 0: dry.
World weightless_block_on_base(double bond_pa) {
  const double a = 0.64;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, 33.23, bond_pa));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 4e-5);
  w.step();
  return w;
}

// A joint that turns as a rigid body keeps its shear spring's stretch (objectivity): the
// law turns last step's stretch into the new contact plane at its old length. A turn of
// 1e-4 rad a step takes the small-angle form (1 + x/2, exact to 3x^2/8), 0.01 rad the
// square root; dropping either shortens the stretch by about 3e-9 or 3e-5 of its length.
TEST(ShearSpring, KeepsItsLengthWhenTheJointTurnsRigidly) {
  World w = weightless_block_on_base(1e9);  // bonded
  State& s = w.state();
  ASSERT_EQ(s.contacts.size(), 4u);
  const Vec3 stretch(3e-6, 4e-6, 0.0);  // m, in the plane z = 0 of last step's normal
  for (double angle : {1e-4, 1e-2}) {
    const Vec3 turned_normal = Eigen::AngleAxisd(angle, Vec3::UnitX()) * Vec3::UnitZ();
    for (std::size_t i = 0; i < 4; ++i) {
      s.contacts.normal[i] = turned_normal;
      s.contacts.shear_stretch_m[i] = stretch;
    }
    for (int k = 0; k < 2; ++k) s.velocity[k] = s.angular_velocity[k] = Vec3::Zero();  // no relative motion
    apply_contact_law(w.model(), s, w.dt_s());
    for (std::size_t i = 0; i < 4; ++i) {
      const Vec3& us = s.contacts.shear_stretch_m[i];
      EXPECT_NEAR(us.norm(), stretch.norm(), 1e-12 * stretch.norm()) << "turn " << angle << ", sub-contact " << i;
      EXPECT_NEAR(us.dot(turned_normal), 0.0, 1e-15 * stretch.norm()) << "turn " << angle << ", sub-contact " << i;
    }
  }
}

// A dry joint that opens while its shear springs are stretched lets them slip free: the
// energy they held, K_s |u_s|^2 / 2 each, is dissipated (booked as friction), and an open
// dry joint stores nothing.
TEST(ShearSpring, ADryJointThatOpensDissipatesWhatItsShearSpringsHeld) {
  World w = weightless_block_on_base(0.0);  // dry
  State& s = w.state();
  SubContacts& c = s.contacts;
  ASSERT_EQ(c.size(), 4u);
  const Vec3 stretch(3e-6, -4e-6, 0.0);  // m, in the joint's plane
  double held_j = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    c.normal_stretch_m[i] = -1e-6;  // loaded in compression last step...
    c.gap_change_m[i] = 2e-6;       // ...and lifted off by twice that in this one
    c.gap_m[i] = 1e-6;
    c.shear_stretch_m[i] = stretch;
    held_j += 0.5 * c.shear_stiffness_n_m[i] * stretch.squaredNorm();
  }
  for (int k = 0; k < 2; ++k) s.velocity[k] = s.angular_velocity[k] = Vec3::Zero();
  const double friction_before = s.energy.friction_j;
  EXPECT_EQ(apply_contact_law(w.model(), s, w.dt_s()), 0.0);  // nothing stored
  EXPECT_NEAR(s.energy.friction_j - friction_before, held_j, 1e-12 * held_j);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(c.flags[i] & SubContactFlag::open) << i;
    EXPECT_EQ(c.shear_stretch_m[i], Vec3::Zero()) << i;
  }
}

// Rotation of a b x h block (b along x) about y after 1 s on a base tilted by theta.
double tipping_rotation(double theta) {
  const double b = 0.32, h = 0.64, depth = 0.64;
  ModelBuilder builder = test::block_on_base(Vec3(b, depth, h), test::stone(1.0, 60.0));
  builder.set_gravity(tilted_gravity(theta));
  World w(builder.build(), 5e-5);
  w.run(20000);
  const Quat q = w.state().orientation[1] * w.model().initial_orientation[1].inverse();
  return Eigen::AngleAxisd(q).angle();
}

TEST(Tipping, BlockTipsIffTanThetaExceedsWidthOverHeight) {
  const double critical = std::atan(0.32 / 0.64);  // 26.57 degrees
  EXPECT_LT(tipping_rotation(critical - deg(2.0)), 1e-3);
  EXPECT_GT(tipping_rotation(critical + deg(2.0)), 0.1);
}

TEST(Vibration, VerticalFrequencyMatchesSpringClosedForm) {
  // Bonded (linear) joint, no gravity, no damping: free vertical vibration.
  const double a = 0.64;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(0.0, 33.23, 1e9));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 1e-5);
  State& s = w.state();
  s.velocity[1] = Vec3(0, 0, -1e-3);
  const double mass = kRho * a * a * a;
  const double kn = test::joint_normal_stiffness(a * a, a / 2, a / 2, kE);
  const double expected = std::sqrt(kn / mass) / (2 * kPi);

  // Times of upward zero crossings of the displacement, linearly interpolated.
  const double z0 = s.position[1].z();
  std::vector<double> crossings;
  double last = 0;
  while (crossings.size() < 11) {
    w.step();
    const double z = s.position[1].z() - z0;
    if (last < 0 && z >= 0) crossings.push_back(s.time_s - w.dt_s() * z / (z - last));
    last = z;
    ASSERT_LT(s.time_s, 1.0);
  }
  const double measured = 10.0 / (crossings.back() - crossings.front());
  EXPECT_NEAR(measured, expected, 0.01 * expected);
}

// A cube on a bonded joint over a base of its own thickness: m_eq = rho (l_A + l_B) S is
// the cube's mass, so the vertical damping ratio is the joint's h. Returns the vertical
// displacement history (m) after an initial downward velocity, sampled every step.
std::vector<double> vertical_free_vibration(double h, double dt, double duration) {
  const double a = 0.64;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(h, 33.23, 1e9));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), dt);
  State& s = w.state();
  s.velocity[1] = Vec3(0, 0, -1e-3);
  const double z0 = s.position[1].z();
  std::vector<double> z;
  while (s.time_s < duration) {
    w.step();
    z.push_back(s.position[1].z() - z0);
  }
  return z;
}

TEST(Vibration, DampingRatioFromLogarithmicDecrementIsTheJointsH) {
  // Light damping, h = 0.05: successive troughs shrink by exp(2 pi zeta / sqrt(1 - zeta^2)).
  const std::vector<double> z = vertical_free_vibration(0.05, 1e-6, 0.01);
  std::vector<double> troughs;
  for (std::size_t i = 1; i + 1 < z.size(); ++i)
    if (z[i] < z[i - 1] && z[i] <= z[i + 1]) troughs.push_back(-z[i]);
  ASSERT_GE(troughs.size(), 6u);
  const double decrement = std::log(troughs[0] / troughs[5]) / 5;
  const double zeta = decrement / std::sqrt(4 * kPi * kPi + decrement * decrement);
  EXPECT_NEAR(zeta, 0.05, 0.01 * 0.05);
}

TEST(Vibration, CriticallyDampedJointPeaksAtOneOverOmega) {
  // h = 1: z(t) = -v0 t exp(-omega t), deepest at t = 1/omega with depth v0 / (e omega).
  const double a = 0.64, dt = 1e-7;
  const double omega = std::sqrt(test::joint_normal_stiffness(a * a, a / 2, a / 2, kE) / (kRho * a * a * a));
  const std::vector<double> z = vertical_free_vibration(1.0, dt, 3.0 / omega);
  const auto deepest = std::min_element(z.begin(), z.end());
  EXPECT_NEAR(-*deepest, 1e-3 / (std::exp(1.0) * omega), 0.005 * 1e-3 / (std::exp(1.0) * omega));
  EXPECT_NEAR((deepest - z.begin() + 1) * dt, 1.0 / omega, 0.01 / omega);
  const double at_three = -1e-3 * 3.0 / omega * std::exp(-3.0);  // creeping back, no overshoot
  EXPECT_NEAR(z.back(), at_three, 0.01 * std::abs(at_three));
}

// Loads the block on a bonded joint with a force ramped from 0 to 1.2 x `capacity` over
// 0.2 s; returns the load at which the first sub-contact lost its bond (or -1).
double ramped_failure_load(const Vec3& direction, double capacity, double normal_load, World& w) {
  State& s = w.state();
  const double h = 0.64;
  const int steps = 10000;
  for (int i = 0; i < steps; ++i) {
    const double load = 1.2 * capacity * i / steps;
    s.applied_force[1] = load * direction + Vec3(0, 0, -normal_load);
    // Apply the load at the joint plane, not the centroid: no overturning couple.
    s.applied_torque[1] = Vec3(0, 0, -h / 2).cross(s.applied_force[1]);
    w.step();
    bool broken = false;
    for_each_sub_contact(s, [&](int i) { broken = broken || (s.contacts.flags[i] & SubContactFlag::broken); });
    if (broken) return load;
  }
  return -1;
}

TEST(Bond, TensionHoldsUpToTensileStrengthTimesArea) {
  const double a = 0.64, ft = 2e5, area = a * a;
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, 33.23, ft));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 2e-5);
  const double failure = ramped_failure_load(Vec3::UnitZ(), ft * area, 0.0, w);
  EXPECT_NEAR(failure, ft * area, 0.01 * ft * area);

  // Once broken, the joint carries no tension: a small pull lifts the block at F / m.
  State& s = w.state();
  const double pull = 0.05 * ft * area, mass = kRho * a * a * a;
  s.applied_force[1] = Vec3(0, 0, pull);
  s.applied_torque[1] = Vec3::Zero();
  w.run(2000);
  const double v1 = s.velocity[1].z();
  w.run(2000);
  EXPECT_NEAR((s.velocity[1].z() - v1) / (2000 * w.dt_s()), pull / mass, 0.01 * pull / mass);
  for_each_sub_contact(s, [&](int i) { EXPECT_EQ(force_on_b(s.contacts, i).norm(), 0.0); });
}

TEST(Bond, ShearHoldsUpToCohesionPlusFriction) {
  const double a = 0.64, c = 2e5, area = a * a, normal = 4e4, tan_phi = std::tan(deg(33.23));
  ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, 33.23, c));
  b.set_gravity(Vec3::Zero());
  World w(b.build(), 2e-5);
  // Settle the normal load first.
  w.state().applied_force[1] = Vec3(0, 0, -normal);
  w.run(2000);
  const double capacity = c * area + normal * tan_phi;
  const double failure = ramped_failure_load(Vec3::UnitX(), capacity, normal, w);
  EXPECT_NEAR(failure, capacity, 0.01 * capacity);
  // After failure only friction resists: the block slides away.
  w.run(2000);
  EXPECT_GT(w.state().velocity[1].x(), 0.1);
}

// How close the bond is to failure (largest_bond_utilisation) under a load held at a share
// of its strength, at rest: tension sigma / f_t; shear (tau + sigma tan phi) / c with the
// normal load's sigma < 0; none for a dry joint.
TEST(Bond, UtilisationIsTheHeldLoadsShareOfTheStrength) {
  const double a = 0.64, h = 0.64, strength = 2e5, area = a * a, normal = 4e4, tan_phi = std::tan(deg(33.23));
  auto held = [&](const Vec3& load) {
    ModelBuilder b = test::block_on_base(Vec3(a, a, a), test::stone(1.0, 33.23, strength));
    b.set_gravity(Vec3::Zero());
    World w(b.build(), 2e-5);
    State& s = w.state();
    s.applied_force[1] = load;
    s.applied_torque[1] = Vec3(0, 0, -h / 2).cross(load);  // at the joint plane: no couple
    w.run(20000);  // 0.4 s, h = 1: at rest
    return largest_bond_utilisation(w.model(), s);
  };
  EXPECT_NEAR(held(Vec3(0, 0, 0.5 * strength * area)), 0.5, 0.005);
  const double shear = 0.6 * (strength * area + normal * tan_phi);
  const double expected = (shear - normal * tan_phi) / (strength * area);  // 0.472
  EXPECT_NEAR(held(Vec3(shear, 0, -normal)), expected, 0.005 * expected);
  EXPECT_NEAR(held(Vec3(0, 0, -normal)), 0.0, 1e-12);  // compression alone: no share of either

  ModelBuilder dry = test::block_on_base(Vec3(a, a, a), test::stone());
  World w(dry.build(), 2e-5);
  w.run(10);
  EXPECT_EQ(largest_bond_utilisation(w.model(), w.state()), -1.0);
}

}  // namespace
}  // namespace ishibashi
