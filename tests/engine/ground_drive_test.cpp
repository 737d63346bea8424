// A block on a base driven kinematically, as the ground drives a bridge: it follows the
// base when glued, and slides as Newmark's rigid-plastic block when friction gives way;
// a driven block turns about the world's axes.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(GroundDrive, HighFrictionBlockFollowsASinusoidalBase) {
  // Dry joint with friction angle 60 degrees (tan = 1.73), 2 Hz, 0.5 g base acceleration:
  // no slip and no rocking (b/h = 1), the block moves with the base up to the joint's
  // tiny elastic deformation.
  ModelBuilder b = test::block_on_base(Vec3(0.64, 0.64, 0.64), test::stone(1.0, 60.0), 0.5, 2.0);
  const Model m = b.build({.drive_fixed_blocks = true});  // the base is block 0, driven
  World w(m, 2e-5);
  State& s = w.state();
  const double a = 0.5 * 9.81, omega = 2 * kPi * 2.0;
  double worst = 0;
  for (int i = 0; i < 50000; ++i) {  // 1 s
    const double t = s.time_s + 0.5 * w.dt_s();
    s.velocity[0] = Vec3(a / omega * (1 - std::cos(omega * t)), 0, 0);
    w.step();
    worst = std::max(worst, std::abs((s.position[1].x() - m.initial_position[1].x()) - (s.position[0].x() - m.initial_position[0].x())));
  }
  const double base_travel = s.position[0].x() - m.initial_position[0].x();
  EXPECT_GT(base_travel, 0.1);
  EXPECT_LT(worst, 1e-4 * base_travel);  // the joint's elastic give only: < 0.01 % of the travel
}

// The driver's angular velocity is in the world's frame: a driven block turned about x, then
// about y, ends turned by R_y R_x (the other order, or turns about its own axes, differ).
TEST(GroundDrive, DrivenBlockTurnsAboutTheWorldsAxes) {
  ModelBuilder b;  // a base slab and a stone far from it, weightless
  const int mat = b.add_material(test::stone());
  const Polyhedron base = make_box(Vec3(0, 0, -0.32), Vec3(2.0, 1.0, 0.64));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const Polyhedron stone = make_box(Vec3(0, 0, 10.0), Vec3(0.4, 0.4, 0.4));
  b.add_block(stone.vertices, stone.faces, mat, Motion::free, "stone");
  b.set_gravity(Vec3::Zero());
  World w(b.build({.drive_fixed_blocks = true}), 1e-3);
  State& s = w.state();
  const int steps = 1000;
  const double rate = 1.5, angle = rate * steps * w.dt_s();  // rad/s; 1.5 rad each way
  for (const Vec3& axis : {Vec3::UnitX(), Vec3::UnitY()})
    for (int i = 0; i < steps; ++i) {
      s.velocity[0] = Vec3::Zero();
      s.angular_velocity[0] = rate * axis;
      w.step();
    }
  const Quat expected = Quat(Eigen::AngleAxisd(angle, Vec3::UnitY())) * Quat(Eigen::AngleAxisd(angle, Vec3::UnitX()));
  const Quat turned = s.orientation[0] * w.model().initial_orientation[0].inverse();
  EXPECT_LT(turned.angularDistance(expected), 1e-9);
}

// Newmark's rigid-plastic sliding block, integrated here on a fine grid: relative
// velocity u' of the block on the base obeys u'' = -a_g - mu g sign(u') while sliding;
// it sticks when u' reaches zero and |a_g| <= mu g.
double newmark_slip(const std::function<double(double)>& ground_accel, double mu, double duration) {
  const double g = 9.81, dt = 1e-6;
  double u = 0, v = 0;
  for (double t = 0; t < duration; t += dt) {
    const double ag = ground_accel(t + 0.5 * dt);
    if (v == 0 && std::abs(ag) <= mu * g) continue;  // stuck
    const double dir = v != 0 ? (v > 0 ? 1.0 : -1.0) : (ag > 0 ? -1.0 : 1.0);
    double vn = v + (-ag - mu * g * dir) * dt;
    if (v != 0 && vn * v < 0) vn = 0;  // stops within the step
    u += 0.5 * (v + vn) * dt;
    v = vn;
  }
  return u;
}

TEST(GroundDrive, SlidingBlockMatchesNewmark) {
  // A wide, low block (no rocking) with friction angle 20 degrees, base pushed by one
  // half-sine pulse of 0.8 g lasting 0.3 s, then moving on at constant speed.
  const double phi = 20.0, mu = std::tan(phi * kPi / 180), amplitude = 0.8 * 9.81, pulse = 0.3;
  auto ground_accel = [&](double t) { return t < pulse ? amplitude * std::sin(kPi * t / pulse) : 0.0; };
  auto ground_velocity = [&](double t) {
    const double tt = std::min(t, pulse);
    return amplitude * pulse / kPi * (1 - std::cos(kPi * tt / pulse));
  };
  const double expected = newmark_slip(ground_accel, mu, 1.2);
  ASSERT_LT(expected, -0.05);  // it slides back several centimetres

  ModelBuilder b = test::block_on_base(Vec3(1.0, 1.0, 0.3), test::stone(1.0, phi), 0.5, 6.0);
  const Model m = b.build({.drive_fixed_blocks = true});  // the base is block 0, driven
  World w(m, 2e-5);
  State& s = w.state();
  w.run(5000);  // settle on its springs first (0.1 s)
  const double start_block = s.position[1].x(), start_base = s.position[0].x(), t0 = s.time_s;
  while (s.time_s - t0 < 1.2) {
    s.velocity[0] = Vec3(ground_velocity(s.time_s - t0 + 0.5 * w.dt_s()), 0, 0);
    w.step();
  }
  const double slip = (s.position[1].x() - start_block) - (s.position[0].x() - start_base);
  EXPECT_NEAR(slip, expected, 0.02 * std::abs(expected));
}

}  // namespace
}  // namespace ishibashi
