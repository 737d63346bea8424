// Bad blocks and bad run settings give a ModelError that names the block and the fault.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/world.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  return "no error";
}

class BadBlock : public ::testing::Test {
 protected:
  std::string add(const Polyhedron& p) {
    return error_of([&] {
      ModelBuilder b;
      const int mat = b.add_material(test::stone());
      const Polyhedron good = make_box(Vec3(5, 5, 5), Vec3(1, 1, 1));
      b.add_block(good.vertices, good.faces, mat, Motion::free, "good");
      b.add_block(p.vertices, p.faces, mat, Motion::free, "bad-one");
    });
  }
};

TEST_F(BadBlock, OpenSurfaceIsNamed) {
  Polyhedron p = make_box(Vec3::Zero(), Vec3(1, 1, 1));
  p.faces.pop_back();
  const std::string e = add(p);
  EXPECT_THAT(e, HasSubstr("block 1 'bad-one'"));
  EXPECT_THAT(e, HasSubstr("open"));
}

TEST_F(BadBlock, NonConvexIsNamed) {
  // An L-shaped prism.
  const Polyhedron p = make_prism({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)}, 0, 1);
  const std::string e = add(p);
  EXPECT_THAT(e, HasSubstr("block 1"));
  EXPECT_THAT(e, HasSubstr("not convex"));
}

TEST_F(BadBlock, InsideOutIsNamed) {
  Polyhedron p = make_box(Vec3::Zero(), Vec3(1, 1, 1));
  for (auto& f : p.faces) std::reverse(f.begin(), f.end());
  EXPECT_THAT(add(p), HasSubstr("inside out"));
}

TEST_F(BadBlock, DegenerateFaceIsNamed) {
  Polyhedron p = make_box(Vec3::Zero(), Vec3(1, 1, 1e-12));
  const std::string e = add(p);
  EXPECT_THAT(e, HasSubstr("block 1"));
  EXPECT_THAT(e, HasSubstr("coincide"));
}

TEST_F(BadBlock, NonPlanarFaceIsNamed) {
  Polyhedron p = make_box(Vec3::Zero(), Vec3(1, 1, 1));
  p.vertices[0].z() -= 0.1;  // bends the bottom face and two sides
  EXPECT_THAT(add(p), HasSubstr("not planar"));
}

TEST_F(BadBlock, NanCoordinateIsNamed) {
  Polyhedron p = make_box(Vec3::Zero(), Vec3(1, 1, 1));
  p.vertices[3].x() = std::nan("");
  EXPECT_THAT(add(p), HasSubstr("not a finite number"));
}

TEST(BadRun, OverlappingInitialBlocksAreNamed) {
  ModelBuilder b = test::block_on_base(Vec3(0.64, 0.64, 0.64), test::stone());
  const Polyhedron p = make_box(Vec3(0.5, 0, 0.42), Vec3(0.64, 0.64, 0.64));  // into block 1 only
  b.add_block(p.vertices, p.faces, 0, Motion::free, "intruder");
  const std::string e = error_of([&] { World(b.build(), 1e-5); });
  EXPECT_THAT(e, HasSubstr("block 1 'block' and block 2 'intruder' overlap by"));
}

TEST(BadRun, TimeStepAboveStabilityLimitIsRefused) {
  const Model m = test::block_on_base(Vec3(0.64, 0.64, 0.64), test::stone(0.0)).build();
  // Cundall's undamped limit 2 sqrt(m / K_n) of the bounce, from the closed form. Rocking
  // on the four corner springs (K_n / 4 at +-a) is stiffer: K_rot = K_n a^2 and
  // I = m (2a)^2 / 6 give omega^2 = 1.5 K_n / m (more with the shear springs), so the
  // bounce limit itself is refused and half of it is safe.
  const double mass = 1880.0 * 0.64 * 0.64 * 0.64;
  const double kn = test::joint_normal_stiffness(0.64 * 0.64, 0.32, 0.32, 1.4039e10);
  const double limit = 2.0 * std::sqrt(mass / kn);
  EXPECT_NO_THROW(World(m, 0.5 * limit));
  const std::string e = error_of([&] { World(m, 1.01 * limit); });
  EXPECT_THAT(e, HasSubstr("exceeds the stability limit"));
  EXPECT_THAT(e, HasSubstr("block 1 'block'"));
}

TEST(BadRun, NanInStateStopsWithBlockName) {
  World w(test::block_on_base(Vec3(0.64, 0.64, 0.64), test::stone()).build(), 1e-5);
  w.state().applied_force[1] = Vec3(std::nan(""), 0, 0);
  const std::string e = error_of([&] { w.step(); });
  EXPECT_THAT(e, HasSubstr("block 1 'block' is not finite"));
}

}  // namespace
}  // namespace ishibashi
