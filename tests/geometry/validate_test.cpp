// CGAL validation finds what is wrong and says where.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace ishibashi
