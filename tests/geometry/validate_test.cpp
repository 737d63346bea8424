// CGAL validation finds what is wrong and says where.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "geometry/shapes.h"
#include "geometry/validate.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

TEST(Validate, TouchingBoxesAreSound) {
  const auto r = validate_blocks({make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)), make_box(Vec3(1, 0.3, 0), Vec3(1, 1, 1))}, {});
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.shared_faces, 1);
  EXPECT_NEAR(r.volume_m3, 2.0, 1e-12);
}

TEST(Validate, OverlapIsReportedWithItsVolume) {
  // Two unit cubes overlapping by 0.2 x 1 x 1.
  const auto r = validate_blocks({make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)), make_box(Vec3(0.8, 0, 0), Vec3(1, 1, 1))},
                                 {"left", "right"});
  ASSERT_EQ(r.overlapping_pairs, 1);
  EXPECT_THAT(r.errors.front(), HasSubstr("block 0 'left'"));
  EXPECT_THAT(r.errors.front(), HasSubstr("block 1 'right'"));
  EXPECT_THAT(r.errors.front(), HasSubstr("overlap by 0.1999"));  // 0.2 less the round-off allowance
}

// Unit cubes at random orientations, the second moved along a random direction until the
// cubes' extents along it overlap by 0.5-15 cm: some pairs then overlap by a thin lens,
// others not at all. Every pair where an edge of one cube reaches 2 mm into the other is reported: their common volume holds at
// least an eighth of a 2 mm ball (4e-9 m^3, above the 1e-9 m^3 tolerance). The inside test is
// the cubes' own, |R^T (x - c)| <= 0.5 - 2 mm along each axis, at 400 points of each edge.
TEST(Validate, EveryThinOverlapOfRotatedCubesIsFound) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto random_unit = [&] { return Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized(); };
  const Polyhedron cube = make_box(Vec3::Zero(), Vec3(1, 1, 1));
  // Whether an edge of the cube (r, c) reaches 2 mm into the cube (r_in, c_in).
  const auto edge_inside = [](const Mat3& r, const Vec3& c, const Mat3& r_in, const Vec3& c_in) {
    for (int axis = 0; axis < 3; ++axis)
      for (int corner = 0; corner < 4; ++corner)
        for (int n = 0; n <= 400; ++n) {
          Vec3 local(corner & 1 ? 0.5 : -0.5, corner & 2 ? 0.5 : -0.5, 0.0);
          std::swap(local[2], local[axis]);
          local[axis] = n / 400.0 - 0.5;
          if ((r_in.transpose() * (r * local + c - c_in)).cwiseAbs().maxCoeff() <= 0.5 - 2e-3) return true;
        }
    return false;
  };
  int overlapping = 0, apart = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Mat3 ra(Eigen::AngleAxisd(6.28 * u(rng), random_unit())), rb(Eigen::AngleAxisd(6.28 * u(rng), random_unit()));
    const Vec3 d = random_unit();
    const double extents = 0.5 * ((ra.transpose() * d).cwiseAbs().sum() + (rb.transpose() * d).cwiseAbs().sum());
    const Vec3 cb = (extents - 0.005 - 0.145 * u(rng)) * d;
    const bool overlap = edge_inside(ra, Vec3::Zero(), rb, cb) || edge_inside(rb, cb, ra, Vec3::Zero());
    const auto r = validate_blocks({transformed(cube, ra, Vec3::Zero()), transformed(cube, rb, cb)}, {});
    if (overlap) EXPECT_EQ(r.overlapping_pairs, 1) << "trial " << trial;
    (overlap ? overlapping : apart) += 1;
  }
  EXPECT_GT(overlapping, 40);  // 61 of the 200 with this seed
  EXPECT_GT(apart, 40);
}

TEST(Validate, BadBlocksAreNamed) {
  Polyhedron open = make_box(Vec3(5, 0, 0), Vec3(1, 1, 1));
  open.faces.pop_back();
  const Polyhedron l_shape = make_prism({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)}, 3, 4);
  Polyhedron inside_out = make_box(Vec3(-5, 0, 0), Vec3(1, 1, 1));
  for (auto& f : inside_out.faces) std::reverse(f.begin(), f.end());
  const auto r = validate_blocks({open, l_shape, inside_out}, {"open", "ell", "flipped"});
  ASSERT_GE(r.errors.size(), 3u);
  EXPECT_THAT(r.errors[0], HasSubstr("'open'"));
  EXPECT_THAT(r.errors[0], HasSubstr("open"));
  EXPECT_THAT(r.errors[1], HasSubstr("'ell'"));
  EXPECT_THAT(r.errors[1], HasSubstr("not convex"));
  EXPECT_THAT(r.errors[2], HasSubstr("'flipped'"));
  EXPECT_THAT(r.errors[2], HasSubstr("inside out"));
}

TEST(Validate, FloatingBlockIsReported) {
  const auto r = validate_blocks({make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)), make_box(Vec3(1, 0, 0), Vec3(1, 1, 1)),
                                  make_box(Vec3(5, 5, 5), Vec3(1, 1, 1))},
                                 {"a", "b", "stray"});
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_THAT(r.errors[0], HasSubstr("'stray'"));
  EXPECT_THAT(r.errors[0], HasSubstr("floats"));
}

// A stone resting on a bad block is not reported as floating as well: the bad block's
// fault is the one error (the ground under an L-shaped stone, then under an open one).
// A stone clear of everything still floats.
TEST(Validate, BlockOnABadBlockIsNotCalledFloating) {
  const Polyhedron ground = make_box(Vec3(0, 0, -0.5), Vec3(10, 10, 1));
  const Polyhedron l_shape = make_prism({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)}, 0, 1);
  Polyhedron open = make_box(Vec3(0, 0, 0.5), Vec3(1, 1, 1));
  open.faces.pop_back();
  for (const Polyhedron& bad : {l_shape, open}) {
    const auto r = validate_blocks({ground, bad}, {"ground", "bad"});
    ASSERT_EQ(r.errors.size(), 1u) << (r.errors.empty() ? std::string("no error") : r.errors.back());
    EXPECT_THAT(r.errors[0], HasSubstr("'bad'"));
  }
  const auto r = validate_blocks({ground, l_shape, make_box(Vec3(0, 0, 9), Vec3(1, 1, 1))}, {"ground", "ell", "stray"});
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_THAT(r.errors[1], HasSubstr("'stray'"));
  EXPECT_THAT(r.errors[1], HasSubstr("floats"));
}

// A corner dragged 2.5 m below its stone's bottom (a mistyped coordinate in an OFF file):
// three faces are no longer planar. In the example's file (tests/fuzz/corpus/off, found by
// fuzzing) CGAL's triangulation of such a face crashed; with this box's face order it was
// called "not convex" by its volume. A face that is not planar, or whose outline crosses
// itself, is now named as such, before anything triangulates it.
TEST(Validate, FaceThatIsNotPlanarIsNamedNotTriangulated) {
  Polyhedron stone = make_box(Vec3(0.2, 0, 0.75), Vec3(0.6, 0.4, 0.3));
  for (Vec3& v : stone.vertices)
    if (v.isApprox(Vec3(-0.1, 0.2, 0.6))) v.z() = -1.9216760180996695;
  const auto r = validate_blocks({stone}, {"dragged"});
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_THAT(r.errors[0], HasSubstr("'dragged'"));
  EXPECT_THAT(r.errors[0], HasSubstr("is not planar: its corners lie up to "));

  // A prism on a pentagram: planar faces, each edge shared by two, every corner of the
  // star turning the same way, but its outline goes round twice (it crosses itself).
  std::vector<Vec3> star;
  for (int k = 0; k < 5; ++k) star.emplace_back(std::cos(0.5 * M_PI + k * 0.8 * M_PI), std::sin(0.5 * M_PI + k * 0.8 * M_PI), 0);
  const auto crossed = validate_blocks({make_prism(star, 0, 1)}, {"star"});
  ASSERT_EQ(crossed.errors.size(), 1u);
  EXPECT_THAT(crossed.errors[0], HasSubstr("'star'"));
  EXPECT_THAT(crossed.errors[0], HasSubstr("its outline crosses itself"));
}

// 2,000 slabs 0.5 x 0.5 m, 0.2 mm thick, tilted 45 degrees and stacked face to face: each
// box overlaps every other's, two million candidate pairs. Validation stops at a million
// and refuses them, naming a block, instead of exhausting the memory (a ring of 100,000
// voussoirs took 17.6 GB to std::bad_alloc).
TEST(Validate, ThinTiltedSlabsSideBySideAreRefusedBeforeTheirPairs) {
  const Mat3 tilt = Eigen::AngleAxisd(0.25 * M_PI, Vec3::UnitX()).toRotationMatrix();
  const double thickness = 2e-4;
  std::vector<Polyhedron> slabs;
  for (int i = 0; i < 2000; ++i)
    slabs.push_back(transformed(make_box(Vec3::Zero(), Vec3(0.5, thickness, 0.5)), tilt, tilt * Vec3(0, i * thickness, 0)));
  const auto r = validate_blocks(slabs, {});
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_THAT(r.errors.front(), HasSubstr("bounding boxes overlap in more than 1000000 pairs"));
  EXPECT_THAT(r.errors.front(), HasSubstr("block "));
  slabs.resize(20);  // twenty: every pair a candidate, none refused
  const auto few = validate_blocks(slabs, {});
  EXPECT_TRUE(few.ok()) << few.errors.front();
  EXPECT_EQ(few.shared_faces, 19);
}

}  // namespace
}  // namespace ishibashi
