// Tie rods (engine/ties.cpp) against closed forms: two free stones in zero gravity joined by
// a snug rod and sent apart. While the rod is taut their relative motion is a mass-spring
// oscillator (reduced mass m/2, stiffness E A / L); it goes slack after half a period, and
// a rod that yields keeps the work F_y * (plastic elongation).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRodArea = 0.25 * kPi * 0.04 * 0.04;  // a 40 mm rod, m^2
constexpr double kSteel = 2.0e11;                      // Pa

// Two 1 m cubes, centroids at x = -1.5 and 1.5 (a 2 m gap: never in contact), and a fixed
// slab far below (block 2), in zero gravity; a rod from `from` to `to` unless no_tie.
ModelBuilder two_stones() {
  ModelBuilder b;
  b.set_gravity(Vec3::Zero());
  const int mat = b.add_material(test::stone());
  for (double x : {-1.5, 1.5}) {
    const Polyhedron cube = make_box(Vec3(x, 0, 0), Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat, Motion::free, x < 0 ? "left" : "right");
  }
  const Polyhedron slab = make_box(Vec3(0, 0, -10), Vec3(1, 1, 1));
  b.add_block(slab.vertices, slab.faces, mat, Motion::fixed, "slab");
  return b;
}

struct TieRun {
  double largest_tension_n = 0.0;
  double slack_at_s = -1.0;  // when the rod first went slack again
};

// Sends the stones apart at `speed` each and steps until the rod has been slack for 100 steps.
TieRun pull_apart(World& w, double speed) {
  State& s = w.state();
  s.velocity[0] = Vec3(-speed, 0, 0);
  s.velocity[1] = Vec3(speed, 0, 0);
  TieRun run;
  for (int i = 0; i < 200000 && (run.slack_at_s < 0 || s.time_s < run.slack_at_s + 100 * w.dt_s()); ++i) {
    w.step();
    run.largest_tension_n = std::max(run.largest_tension_n, s.tie_tension_n[0]);
    if (run.slack_at_s < 0 && run.largest_tension_n > 0 && s.tie_tension_n[0] == 0) run.slack_at_s = s.time_s;
  }
  return run;
}

TEST(Ties, ATautRodIsASpringOfEAOverLThatGoesSlackAfterHalfAPeriod) {
  ModelBuilder b = two_stones();
  b.add_tie(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0), kRodArea, kSteel, 2.35e8);
  World w(b.build(), 1e-5);
  const double m = w.model().mass_kg[0];
  const double k = kSteel * kRodArea / 2.4;
  ASSERT_NEAR(w.model().ties[0].stiffness_n_m, k, 1e-6 * k);
  const double omega = std::sqrt(k / (0.5 * m)), speed = 0.05;
  const TieRun run = pull_apart(w, speed);
  // Relative speed 2 v, reduced mass m / 2: the largest stretch 2 v / omega.
  EXPECT_NEAR(run.largest_tension_n, k * 2 * speed / omega, 2e-3 * k * 2 * speed / omega);
  EXPECT_NEAR(run.slack_at_s, kPi / omega, 3 * w.dt_s());
  // Elastic: they come back at the speed they left with, and a slack rod pushes nothing;
  // its peak (summary.json's peak_tie_tension_n) stays.
  const State& s = w.state();
  EXPECT_EQ(s.tie_tension_n[0], 0.0);
  EXPECT_EQ(s.tie_peak_tension_n[0], run.largest_tension_n);
  EXPECT_NEAR(s.tie_peak_tension_n[0], k * 2 * speed / omega, 2e-3 * k * 2 * speed / omega);
  EXPECT_NEAR(s.velocity[0].x(), speed, 1e-3 * speed);
  EXPECT_NEAR(s.velocity[1].x(), -speed, 1e-3 * speed);
  EXPECT_EQ(s.tie_plastic_m[0], 0.0);
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 1e-4 * 0.5 * 2 * m * speed * speed);
}

TEST(Ties, AYieldingRodKeepsTheWorkOfItsPlasticElongation) {
  ModelBuilder b = two_stones();
  const double yield_force = 1e4;  // N, well below the 31 kN the pull would reach elastically
  b.add_tie(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0), kRodArea, kSteel, yield_force / kRodArea);
  World w(b.build(), 1e-5);
  const double m = w.model().mass_kg[0], k = kSteel * kRodArea / 2.4, speed = 0.05;
  const TieRun run = pull_apart(w, speed);
  const State& s = w.state();
  // Kinetic energy of the relative motion, 0.5 (m/2) (2 v)^2, goes into the rod: F_y^2 / 2k
  // elastic (given back) and F_y * p plastic.
  const double relative = 0.5 * (0.5 * m) * 4 * speed * speed, elastic = yield_force * yield_force / (2 * k);
  const double plastic = (relative - elastic) / yield_force;
  EXPECT_DOUBLE_EQ(run.largest_tension_n, yield_force);
  EXPECT_NEAR(s.tie_plastic_m[0], plastic, 5e-3 * plastic);
  EXPECT_NEAR(s.energy.tie_yield_j, relative - elastic, 5e-3 * relative);
  const double speed_after = 0.5 * std::sqrt(2 * elastic / (0.5 * m));
  EXPECT_NEAR(s.velocity[1].x(), -speed_after, 5e-3 * speed_after);
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 1e-3 * relative);
}

TEST(Ties, APretensionedRodPressesItsJointTillTheJointAndTheRodShareIt) {
  // Two cubes face to face (centroids at x = -0.5 and 0.5), zero gravity, a rod through
  // both pretensioned to T0: the joint (K_n = S / (l/E + l/E) = E for S = 1 m^2, l = 0.5 m)
  // closes by d and the rod (k = E_s A / L) loses k d of its stretch, so at rest
  // K d = T0 - k d: the rod keeps T = T0 K / (K + k).
  ModelBuilder b;
  b.set_gravity(Vec3::Zero());
  const Material stone = test::stone(1.0);
  const int mat = b.add_material(stone);
  for (double x : {-0.5, 0.5}) {
    const Polyhedron cube = make_box(Vec3(x, 0, 0), Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat);
  }
  const double area = 1e-2, length = 1.6, pretension = 5e4;  // a 113 mm bar: as stiff as the joint, nearly
  b.add_tie(Vec3(-0.8, 0, 0), Vec3(0.8, 0, 0), area, kSteel, 2.35e8, pretension);
  const Model model = b.build();
  World w(model, 0.5 * World(model, 1e-9).critical_time_step_s());
  w.run(static_cast<long>(0.05 / w.dt_s()));  // 0.05 s: tens of the joint's periods
  const double joint = stone.young_pa, rod = kSteel * area / length;
  const double expected = pretension * joint / (joint + rod);
  EXPECT_NEAR(w.state().tie_tension_n[0], expected, 1e-4 * expected);
  EXPECT_LT(expected, 0.95 * pretension);  // the joint took a share worth telling apart

  // An ensemble member's stones are placed a little differently (analysis/run/member_draw):
  // its rods are made snug again, each at its pretension where its stones now stand.
  Model moved = model;
  moved.initial_position[1].x() += 1e-3;
  make_ties_snug(moved);
  EXPECT_NEAR(moved.ties[0].rest_length_m, length + 1e-3 - pretension / rod, 1e-12);  // rod: E A / L
}

TEST(Ties, AnOffCentreRodTurnsTheStonesAndConservesMomentum) {
  // Anchors 0.3 m off the axis: the rod's moments turn both stones; total linear and
  // angular momentum (about the origin) stay zero, as the rod's forces are internal.
  ModelBuilder b = two_stones();
  b.add_tie(Vec3(-1.2, 0.3, 0.1), Vec3(1.2, 0.3, -0.2), kRodArea, kSteel, 2.35e8);
  World w(b.build(), 1e-5);
  pull_apart(w, 0.05);
  const Model& m = w.model();
  const State& s = w.state();
  Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
  for (int i = 0; i < 2; ++i) {
    const Mat3 r = s.orientation[i].toRotationMatrix();
    linear += m.mass_kg[i] * s.velocity[i];
    angular += s.position[i].cross(m.mass_kg[i] * s.velocity[i]) +
               r * m.inertia_kg_m2[i].cwiseProduct(r.transpose() * s.angular_velocity[i]);
  }
  const double scale = m.mass_kg[0] * 0.05;  // momentum of one stone sent off
  EXPECT_GT(s.angular_velocity[0].norm(), 1e-4);  // it did turn them
  EXPECT_LT(linear.norm(), 1e-9 * scale);
  EXPECT_LT(angular.norm(), 1e-6 * scale);
}

TEST(Ties, TheRodSetsTheStableStep) {
  // No contacts: the limit is the rod's, 2 / omega with omega^2 = 2 k / m (two free stones
  // pulled against each other, counted as a joint between free blocks is).
  ModelBuilder b = two_stones();
  b.add_tie(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0), kRodArea, kSteel, 2.35e8);
  const Model model = b.build();
  const double k = kSteel * kRodArea / 2.4, limit = 2.0 / std::sqrt(2 * k / model.mass_kg[0]);
  EXPECT_NEAR(World(model, 1e-5).critical_time_step_s(), limit, 1e-9 * limit);
  EXPECT_THROW(World(model, 1.1 * limit), ModelError);
}

std::string tie_error(const Vec3& from, const Vec3& to, double pretension_n = 0) {
  ModelBuilder b = two_stones();
  try {
    b.add_tie(from, to, kRodArea, kSteel, 2.35e8, pretension_n);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(Ties, AnAnchorOutsideOneFreeStoneOrAPretensionPastYieldIsAnError) {
  EXPECT_THAT(tie_error(Vec3(0, 0, 0), Vec3(1.2, 0, 0)), HasSubstr("(0, 0, 0) m lies in no block"));
  EXPECT_THAT(tie_error(Vec3(-1.2, 0, 0), Vec3(1.0, 0, 0)), HasSubstr("lies on a face of block 1 'right'"));
  EXPECT_THAT(tie_error(Vec3(-1.2, 0, 0), Vec3(0, 0, -10)), HasSubstr("block 2 'slab', which does not move"));
  EXPECT_THAT(tie_error(Vec3(-1.2, 0, 0), Vec3(-1.8, 0, 0)), HasSubstr("both anchors lie in block 0 'left'"));
  EXPECT_EQ(tie_error(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0)), "");
  EXPECT_EQ(tie_error(Vec3(-1.2, 0, 0), Vec3(1.2, 0, 0), 3e5),  // 40 mm S235: yields at 295 kN
            "tie 0: its pretension 300000 N must be >= 0 and below its yield force 295310 N");
}

}  // namespace
}  // namespace ishibashi
