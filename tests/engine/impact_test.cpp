// Impacts against closed forms: the restitution of a face-first drop, energy never
// created by edge-first and corner-first drops, and a stone that slides off a tilted
// stone with the speed that its energy allows.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

// A fixed base (top at z = 0, as thick as the cube) and a cube of edge a whose lowest
// face is `gap` above it; no gravity unless given.
World cube_above_base(double a, double gap, const Material& material, double dt, const Vec3& gravity = Vec3::Zero(),
                      Damping damping = Damping::study) {
  ModelBuilder b;
  const int mat = b.add_material(material);
  const Polyhedron base = make_box(Vec3(0, 0, -0.5 * a), Vec3(4.0, 4.0, a));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const Polyhedron cube = make_box(Vec3(0, 0, gap + 0.5 * a), Vec3(a, a, a));
  b.add_block(cube.vertices, cube.faces, mat, Motion::free, "cube");
  b.set_gravity(gravity);
  return World(b.build({.damping = damping}), dt);
}

// Face-first drop at v0 without gravity: the four corner sub-contacts act as one linear
// spring-dashpot K = 4 k_n, C = 4 c_n on the cube's mass; with a base as thick as the
// cube, m_eq of MODEL.md is the cube's mass, so the damping ratio of the impact is h.
// Returns the rebound speed over the impact speed (0 when it never leaves the base).
// With implicit dashpots, dt is `share` of the springs' limit.
double face_drop_restitution(double h, bool* stayed_in_contact = nullptr, Damping damping = Damping::study,
                             double share = 0) {
  const double a = 0.64, v0 = 1.0;
  const double dt = damping == Damping::implicit
                        ? share * cube_above_base(a, 1e-4, test::stone(h), 1e-9, Vec3::Zero(), damping).critical_time_step_s()
                        : 1e-6;
  World w = cube_above_base(a, 1e-4, test::stone(h), dt, Vec3::Zero(), damping);
  State& s = w.state();
  s.velocity[1] = Vec3(0, 0, -v0);
  bool touched = false, left = false;
  const double omega = std::sqrt(test::joint_normal_stiffness(a * a, a / 2, a / 2, 1.4039e10) / (1.88e3 * a * a * a));
  while (s.time_s < 1e-4 / v0 + 20.0 / omega) {  // the approach and twenty contact times
    w.step();
    const bool in_contact = s.force[1].norm() > 0;
    touched = touched || in_contact;
    if (touched && !in_contact) {
      left = true;
      break;
    }
  }
  if (stayed_in_contact) *stayed_in_contact = touched && !left;
  EXPECT_LT(std::abs(s.velocity[1].x()) + std::abs(s.velocity[1].y()), 1e-9 * v0);  // a square hit: no tilt
  return left ? s.velocity[1].z() / v0 : 0.0;
}

TEST(Impact, FaceFirstDropReboundsWithSpringDashpotRestitution) {
  for (double zeta : {0.05, 0.2, 0.5, 0.8}) {
    const double expected = std::exp(-kPi * zeta / std::sqrt(1 - zeta * zeta));
    EXPECT_NEAR(face_drop_restitution(zeta), expected, 0.02 * expected) << "zeta " << zeta;
  }
}

// The same drop with the dashpots implicit (backward Euler), at a share of the springs'
// limit (issue 45 item 2: what the study's step, 0.61-0.65 of the limit for models B-F,
// costs an impact). A contact resolved by a few steps dissipates too little: at 0.8 of
// the limit the rebound of zeta 0.2 is 10 % and of zeta 0.5 137 % above the closed form,
// within 3 % at 1/80 of the limit (measured: 0.4 -> +4 / +31 %, 0.1 -> +4 / +19 %, the
// error jumping with the step in which the contact ends). With the study's h = 1 the
// closed form does not rebound at all; the implicit step rebounds at 7, 2.6, 1.1 and
// 0.2 % of the impact speed at 0.8, 0.64, 0.4 and 0.2 of the limit.
TEST(Impact, FaceFirstDropWithImplicitDashpotsConvergesAsDtFalls) {
  for (double zeta : {0.2, 0.5}) {
    const double expected = std::exp(-kPi * zeta / std::sqrt(1 - zeta * zeta));
    const double coarse = face_drop_restitution(zeta, nullptr, Damping::implicit, 0.8) / expected - 1;
    const double fine = face_drop_restitution(zeta, nullptr, Damping::implicit, 0.0125) / expected - 1;
    EXPECT_GT(coarse, 0.05) << "zeta " << zeta;  // too little dissipated when coarse
    EXPECT_LT(std::abs(fine), 0.03) << "zeta " << zeta;
  }
  double last = INFINITY;
  for (double share : {0.8, 0.64, 0.4, 0.2}) {
    const double rebound = face_drop_restitution(1.0, nullptr, Damping::implicit, share);
    EXPECT_LT(rebound, share <= 0.64 ? 0.03 : 0.08) << share;
    EXPECT_LT(rebound, last) << share;
    last = rebound;
  }
  EXPECT_LT(last, 0.005);
}

TEST(Impact, FaceFirstDropDoesNotReboundWhenCriticallyOrOverDamped) {
  for (double zeta : {1.0, 1.5}) {
    bool stayed = false;
    face_drop_restitution(zeta, &stayed);
    EXPECT_TRUE(stayed) << "zeta " << zeta;
  }
}

// A stone of 0.64 x 0.48 x 0.32 m dropped at a random orientation, so that it lands on
// an edge or a corner, bounces and tumbles on the base. Mechanical energy (kinetic +
// gravitational + spring) can only fall: returns the largest rise above the start (J)
// and, through `dropped`, the potential energy released by the end.
struct DropResult {
  double initial_j, worst_rise_j, final_mechanical_j, dissipated_j, balance_error_j;
  bool landed;
};

DropResult random_drop(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), height(0.05, 0.5), damping(0.05, 1.0);
  ModelBuilder b;
  const int mat = b.add_material(test::stone(damping(rng), 33.23));
  const Polyhedron base = make_box(Vec3(0, 0, -0.32), Vec3(4.0, 4.0, 0.64));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  Quat q(1.0, unit(rng), unit(rng), unit(rng));
  q.normalize();
  Polyhedron stone = make_box(Vec3::Zero(), Vec3(0.64, 0.48, 0.32));
  double lowest = 0;
  for (Vec3& v : stone.vertices) {
    v = q * v;
    lowest = std::min(lowest, v.z());
  }
  const Vec3 start(0.3 * unit(rng), 0.3 * unit(rng), height(rng) - lowest);
  for (Vec3& v : stone.vertices) v += start;
  b.add_block(stone.vertices, stone.faces, mat, Motion::free, "stone");
  World w(b.build(), 2e-5);
  State& s = w.state();
  s.angular_velocity[1] = Vec3(unit(rng), unit(rng), unit(rng));
  w.step();
  DropResult r{s.energy.mechanical_j(), 0.0, 0.0, 0.0, 0.0, false};
  for (int i = 0; i < 25000; ++i) {  // 0.5 s: the fall, the impact and the tumble
    w.step();
    r.worst_rise_j = std::max(r.worst_rise_j, s.energy.mechanical_j() - r.initial_j);
    r.landed = r.landed || sub_contact_count(s) > 0;
  }
  r.final_mechanical_j = s.energy.mechanical_j();
  r.dissipated_j = s.energy.damping_j + s.energy.friction_j;
  r.balance_error_j = s.energy.balance_error_j();
  return r;
}

TEST(Impact, EdgeAndCornerDropsNeverGainEnergy) {
  std::mt19937 rng(20261123);
  const double released_scale = 1.88e3 * 0.64 * 0.48 * 0.32 * kG * 0.05;  // m g h of the lowest drop
  double worst_rise = 0, worst_balance = 0;
  for (int drop = 0; drop < 200; ++drop) {
    const DropResult r = random_drop(rng);
    ASSERT_TRUE(r.landed) << "drop " << drop;
    EXPECT_LE(r.final_mechanical_j, r.initial_j) << "drop " << drop;
    worst_rise = std::max(worst_rise, r.worst_rise_j / released_scale);
    worst_balance = std::max(worst_balance, std::abs(r.balance_error_j) / r.dissipated_j);
    EXPECT_LT(r.worst_rise_j, 1e-3 * released_scale) << "drop " << drop;
    EXPECT_LT(std::abs(r.balance_error_j), 0.01 * r.dissipated_j) << "drop " << drop;
  }
  std::printf("worst rise of mechanical energy %.3g of the smallest m g h; worst balance error %.3g of the dissipated\n",
              worst_rise, worst_balance);
}

TEST(Impact, StoneSlidingOffATiltedStoneLeavesWithTheSpeedEnergyAllows) {
  // A 0.64 m cube on a 3 m slab tilted by 40 degrees (gravity tilted, slope down +x),
  // friction 33.23 degrees: it slides at a = g (sin - cos tan phi) and, past the lower
  // edge, tips over it and falls off.
  const double theta = 40.0 * kPi / 180.0, phi = 33.23 * kPi / 180.0, a = 0.64;
  ModelBuilder b;
  const int mat = b.add_material(test::stone(0.2, 33.23));
  const Polyhedron slab = make_box(Vec3(0, 0, -0.32), Vec3(3.0, 2.0, 0.64));
  b.add_block(slab.vertices, slab.faces, mat, Motion::fixed, "slab");
  const Polyhedron cube = make_box(Vec3(-1.0, 0, 0.5 * a), Vec3(a, a, a));
  b.add_block(cube.vertices, cube.faces, mat, Motion::free, "stone");
  b.set_gravity(kG * Vec3(std::sin(theta), 0, -std::cos(theta)));
  World w(b.build(), 2e-5);
  State& s = w.state();
  const double accel = kG * (std::sin(theta) - std::cos(theta) * std::tan(phi));
  // Until its front face reaches the edge it slides on its whole base (once it overhangs,
  // the contact cannot hold the friction's overturning moment for long and it tips).
  const double x0 = s.position[1].x(), front_at_edge = 1.5 - 0.5 * a;
  bool passed_edge = false;
  while (s.time_s < 3.0) {
    w.step();
    if (!passed_edge && s.position[1].x() >= front_at_edge) {
      passed_edge = true;
      const double expected = std::sqrt(2 * accel * (s.position[1].x() - x0));
      EXPECT_NEAR(s.velocity[1].x(), expected, 0.01 * expected);
    }
    if (passed_edge && sub_contact_count(s) == 0) break;  // it left the slab
  }
  ASSERT_TRUE(passed_edge);
  ASSERT_EQ(sub_contact_count(s), 0) << "still on the slab after 3 s";
  // Off the slab, its kinetic energy is what gravity released less what friction and
  // the dashpots took, plus what the re-clips of its tip over the edge made (0.25 J): no
  // more. (Friction booked as the limit after each step times its slip left 0.32 J, first
  // order in dt, out of what it took.)
  const double released = s.energy.initial_total_j - s.energy.gravitational_j;
  const double lost = s.energy.friction_j + s.energy.damping_j;
  EXPECT_NEAR(s.energy.kinetic_j, released - lost, 0.01 * (released - lost));
  EXPECT_LE(s.energy.kinetic_j, released - lost + s.energy.reclip_j + 1e-6 * released);
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 1e-5 * released);
}

TEST(Ground, StoneFallingPastTheGroundIsFrozenAndItsEnergyBooked) {
  // A stone beside a 1 m base (top at z = 0, 0.64 m thick) falls past it, spinning: below
  // the base by more than a block size it is frozen, with the kinetic energy it had booked
  // (its fall's and its spin's).
  ModelBuilder b;
  const int mat = b.add_material(test::stone(0.5));
  const Polyhedron base = make_box(Vec3(0, 0, -0.32), Vec3(1.0, 1.0, 0.64));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const Polyhedron stone = make_box(Vec3(2.0, 0, 0.5), Vec3(0.4, 0.4, 0.4));
  b.add_block(stone.vertices, stone.faces, mat, Motion::free, "stone");
  World w(b.build(), 1e-4);
  const double leave = 0.64 + std::cbrt(1.0 * 1.0 * 0.64);  // the base's bottom plus the largest block size
  EXPECT_NEAR(w.model().leave_depth_m, leave, 1e-12);
  State& s = w.state();
  const double spin = 3.0;  // rad/s about z; a cube's spin stays as it is
  s.angular_velocity[1] = Vec3(0, 0, spin);
  while (s.time_s < 2.0) w.step();
  EXPECT_EQ(s.left_model[1], 1);
  EXPECT_EQ(s.velocity[1].norm(), 0.0);
  EXPECT_EQ(s.angular_velocity[1].norm(), 0.0);
  // It was frozen at the first step below the leave depth, having fallen from z = 0.5.
  EXPECT_NEAR(s.position[1].z(), -leave, 0.01);
  const double mass = 1.88e3 * 0.4 * 0.4 * 0.4, fall = 0.5 - s.position[1].z();
  const double spin_j = 0.5 * (mass * 0.4 * 0.4 / 6) * spin * spin;  // 14.4 J
  EXPECT_NEAR(s.energy.left_model_j, mass * kG * fall + spin_j, 1e-3 * mass * kG * fall);
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 1e-6 * s.energy.left_model_j);
}

}  // namespace
}  // namespace ishibashi
