// Motion without contacts: free fall and torque-free rotation (Euler's equations).
#include <gtest/gtest.h>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

TEST(FreeMotion, FreeFallFollowsParabola) {
  ModelBuilder b;
  const int mat = b.add_material(test::stone());
  const Polyhedron p = make_box(Vec3(0, 0, 10), Vec3(0.5, 0.4, 0.3));
  b.add_block(p.vertices, p.faces, mat);
  World w(b.build(), 1e-4);
  w.state().velocity[0] = Vec3(1.0, 0, 2.0);
  w.run(10000);
  const double t = w.state().time_s, g = 9.81;
  EXPECT_NEAR(t, 1.0, 1e-12);
  // Semi-implicit Euler is first order: the drop differs by g t dt / 2 = 4.9e-4 m.
  EXPECT_NEAR(w.state().position[0].z(), 10.0 + 2.0 * t - 0.5 * g * t * t, 1e-3);
  EXPECT_NEAR(w.state().position[0].x(), 1.0 * t, 1e-12);
  EXPECT_NEAR(w.state().velocity[0].z(), 2.0 - g * t, 1e-9);
}

TEST(FreeMotion, TorqueFreeRotationConservesAngularMomentumAndEnergy) {
  // An asymmetric block spinning mostly about its stable (largest-inertia) axis with a
  // wobble: Euler's equations make omega precess while L (world) and energy stay fixed.
  ModelBuilder b;
  b.set_gravity(Vec3::Zero());
  const int mat = b.add_material(test::stone());
  const Polyhedron p = make_box(Vec3::Zero(), Vec3(1.0, 0.6, 0.3));
  b.add_block(p.vertices, p.faces, mat);
  World w(b.build(), 1e-5);
  State& s = w.state();
  const Model& m = w.model();
  s.angular_velocity[0] = Vec3(0.3, 0.5, 4.0);
  auto momentum = [&] {
    const Mat3 r = s.orientation[0].toRotationMatrix();
    return Vec3(r * m.inertia_kg_m2[0].cwiseProduct(r.transpose() * s.angular_velocity[0]));
  };
  auto energy = [&] {
    const Vec3 wb = s.orientation[0].toRotationMatrix().transpose() * s.angular_velocity[0];
    return 0.5 * wb.dot(m.inertia_kg_m2[0].cwiseProduct(wb));
  };
  const Vec3 l0 = momentum();
  const double e0 = energy();
  w.run(100000);  // 1 s, several precession periods
  EXPECT_LT((momentum() - l0).norm() / l0.norm(), 2e-3);
  EXPECT_LT(std::abs(energy() - e0) / e0, 2e-3);
  // omega really moved: the wobble makes it differ from its start.
  EXPECT_GT((s.angular_velocity[0] - Vec3(0.3, 0.5, 4.0)).norm(), 0.05);
}

}  // namespace
}  // namespace ishibashi
