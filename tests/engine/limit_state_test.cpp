// Masonry limit states against the classical closed forms: a semicircular arch under
// its own weight needs a thickness of t/R = 0.1075 (Milankovitch; Heyman), collapsing
// with hinges near the haunches; a block on a base accelerated horizontally starts to
// rock when the acceleration exceeds g b/h (Housner).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/joints.h"
#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

// A semicircular arch of `count` voussoirs with radial joints, centre-line radius R,
// thickness t, 1 m wide, all free, standing on a fixed base (top at z = 0) with its
// springing joints on the base. Friction 60 degrees: nothing slides.
Model semicircular_arch(double radius, double thickness, int count, JointRule rule) {
  ModelBuilder b;
  const int mat = b.add_material(test::stone(1.0, 60.0));
  const Polyhedron base = make_box(Vec3(0, 0, -0.25), Vec3(3 * radius, 2.0, 0.5));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const double inner = radius - thickness / 2, outer = radius + thickness / 2;
  for (int k = 0; k < count; ++k) {
    const double a0 = kPi * k / count, a1 = kPi * (k + 1) / count;  // from the +x springing
    const std::vector<Vec3> polygon{{inner * std::cos(a0), 0, inner * std::sin(a0)},
                                    {outer * std::cos(a0), 0, outer * std::sin(a0)},
                                    {outer * std::cos(a1), 0, outer * std::sin(a1)},
                                    {inner * std::cos(a1), 0, inner * std::sin(a1)}};
    const Polyhedron v = make_prism_xz(polygon, -0.5, 0.5);
    b.add_block(v.vertices, v.faces, mat, Motion::free, "voussoir-" + std::to_string(k));
  }
  return b.build({.joint_rule = rule});
}

struct ArchOutcome {
  double crown_drop_m;
  std::vector<double> hinge_angles_deg;  // joints open by more than 1 mm, angle from the crown
};

// Runs the arch under gravity until the crown has dropped by `stop_drop_m` or for
// `duration_s`.
ArchOutcome load_arch(double t_over_r, double duration_s, double stop_drop_m, JointRule rule = JointRule::corners) {
  const double radius = 5.0;
  const int count = 36;  // 5 degrees each: joints at 50, 55, 60 degrees from the crown
  World w(semicircular_arch(radius, t_over_r * radius, count, rule), 1e-5);
  State& s = w.state();
  Joints joints = find_original_joints(s);
  const int crown = 1 + count / 2;  // the voussoir just past the crown (joint 18 is at the crown)
  const double z0 = s.position[crown].z();
  while (s.time_s < duration_s && z0 - s.position[crown].z() < stop_drop_m) w.run(500);
  ArchOutcome out{z0 - s.position[crown].z(), {}};
  measure_joints(s, JointThresholds{}, joints);
  for (int j = 0; j < joints.size(); ++j) {
    if (joints.opening_m[j] < 1e-3) continue;
    Vec3 centre = s.position[joints.block_a[j]] + s.orientation[joints.block_a[j]] * joints.centre_on_a[j];
    out.hinge_angles_deg.push_back(std::atan2(std::abs(centre.x()), centre.z()) * 180 / kPi);
  }
  return out;
}

TEST(LimitState, SemicircularArchStandsAtTOverR012) {
  const ArchOutcome o = load_arch(0.12, 1.0, 0.05);
  EXPECT_LT(o.crown_drop_m, 1e-3);
  EXPECT_TRUE(o.hinge_angles_deg.empty());
}

TEST(LimitState, SemicircularArchCollapsesAtTOverR010WithHingesAtTheHaunches) {
  const ArchOutcome o = load_arch(0.10, 4.0, 0.02);
  ASSERT_GE(o.crown_drop_m, 0.02) << "the crown did not drop: the arch stands";
  // Five hinges: the crown, both haunches, both springings. The haunch hinges lie at
  // 54 to 59 degrees from the crown in the published solutions: here the joint at 55.
  int haunches = 0;
  for (double angle : o.hinge_angles_deg) {
    std::printf("hinge at %.1f degrees from the crown\n", angle);
    if (angle > 20 && angle < 80) {
      ++haunches;
      EXPECT_GT(angle, 52.0);
      EXPECT_LT(angle, 59.0);
    }
  }
  EXPECT_EQ(haunches, 2);
}

// Rotation of a b x h block (b along x) after `duration` s on a base whose acceleration
// rises smoothly to `accel` (m/s^2, along x) in 0.05 s and then stays.
// With implicit dashpots, dt is `share` of the springs' limit (else 2e-5 s).
double rocking_after(double accel, double duration, JointRule rule = JointRule::corners, Damping damping = Damping::study,
                     double share = 0) {
  const double b = 0.32, h = 0.64;
  ModelBuilder builder;
  const int mat = builder.add_material(test::stone(1.0, 60.0));  // tan(60) > b/h: no sliding
  const Polyhedron base = make_box(Vec3(0, 0, -0.32), Vec3(4.0, 4.0, 0.64));
  builder.add_block(base.vertices, base.faces, mat, Motion::prescribed, "base");
  const Polyhedron block = make_box(Vec3(0, 0, h / 2), Vec3(b, 0.64, h));
  builder.add_block(block.vertices, block.faces, mat, Motion::free, "block");
  const Model model = builder.build({.joint_rule = rule, .damping = damping});
  World w(model, damping == Damping::implicit ? share * World(model, 1e-9).critical_time_step_s() : 2e-5);
  State& s = w.state();
  w.run(std::lround(0.05 / w.dt_s()));  // settle on the base
  const double t0 = s.time_s;
  double angle = 0;
  while (s.time_s - t0 < duration) {
    const double t = s.time_s - t0;
    s.velocity[0].x() = t < 0.05 ? accel * t * t / 0.1 : accel * (t - 0.025);
    w.step();
    const Quat q = s.orientation[1] * w.model().initial_orientation[1].inverse();
    angle = std::max(angle, Eigen::AngleAxisd(q).angle());
  }
  return angle;
}

TEST(LimitState, BlockStartsRockingWhenGroundAccelerationExceedsGTimesBOverH) {
  const double critical = kG * 0.32 / 0.64;
  EXPECT_LT(rocking_after(0.95 * critical, 0.3), 1e-4);
  EXPECT_GT(rocking_after(1.05 * critical, 0.3), 1e-2);
}

// Housner's onset with the dashpots implicit at the study's share of the springs' limit
// (its 4e-5 s is 0.61-0.65 of it for models B-F) and at a fifth of it: the block holds
// below g b/h and rocks above (issue 45 item 2; measured: turned 3.6e-6 and 3.3e-6 rad at
// 0.95 g b/h after 0.3 s, 0.0165 rad at 1.05 g b/h, as the explicit step gives).
TEST(LimitState, ImplicitDashpotsKeepHousnersOnset) {
  const double critical = kG * 0.32 / 0.64;
  for (double share : {0.64, 0.2}) {
    EXPECT_LT(rocking_after(0.95 * critical, 0.3, JointRule::corners, Damping::implicit, share), 1e-4) << share;
    EXPECT_GT(rocking_after(1.05 * critical, 0.3, JointRule::corners, Damping::implicit, share), 1e-2) << share;
  }
}

// The moment rule keeps a point at every corner of a joint, so a joint still hinges about
// its edge: the same limit states as the corner rule. Its joints are a third as stiff in
// rocking and their interior points lift off as the thrust nears an edge, so below the
// limit they turn further before they hold (measured: the block at 0.8, 0.9, 0.95 of
// g b/h turns 2.3e-5, 1.1e-4, 1.9e-4 rad against 3e-6 with corners): what tells a standing
// structure there is that it stops moving.
// The arch at t/R = 0.12 sways on its soft joints by about a millimetre (1.3, 1.6, 0.7, 0.9
// mm after 1, 2, 4, 8 s, measured) without a hinge; at 0.11 it collapses, where the corner
// rule's still stands: thrust at the edge of a joint bears on its corner points, a
// twelfth of the joint's stiffness here against a half with corners, so the hinges form
// a little inside the edges and the arch needs 0.11-0.12 rather than the classical 0.1075.
TEST(LimitState, MomentRuleArchStandsAtTOverR012AndCollapsesAtTOverR010) {
  const ArchOutcome stands = load_arch(0.12, 4.0, 0.05, JointRule::moments);
  EXPECT_LT(stands.crown_drop_m, 2e-3);
  EXPECT_TRUE(stands.hinge_angles_deg.empty());
  const ArchOutcome falls = load_arch(0.10, 4.0, 0.02, JointRule::moments);
  EXPECT_GE(falls.crown_drop_m, 0.02) << "the crown did not drop: the arch stands";
}

TEST(LimitState, MomentRuleBlockStartsRockingWhenGroundAccelerationExceedsGTimesBOverH) {
  const double critical = kG * 0.32 / 0.64;
  const double held = rocking_after(0.95 * critical, 0.3, JointRule::moments);
  EXPECT_LT(held, 1e-3);
  EXPECT_NEAR(rocking_after(0.95 * critical, 0.6, JointRule::moments), held, 0.01 * held) << "the block still turns";
  EXPECT_GT(rocking_after(1.05 * critical, 0.3, JointRule::moments), 1e-2);
}

}  // namespace
}  // namespace ishibashi
