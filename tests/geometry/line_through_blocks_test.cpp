#include "geometry/line_through_blocks.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ishibashi {
namespace {

BridgeBlock box(const Vec3& centre, const Vec3& size, bool fixed = false) {
  return BridgeBlock{make_box(centre, size), Part::imported, 0, fixed};
}

// A box from y = -0.5 to 0.7, a second one past a gap up to y = 1.5, a fixed one further on:
// the line along y spans the free ones, the gap included, and leaves the fixed one out; a
// line through an edge at a point meets nothing, one along the edges spans both.
TEST(LineThroughBlocks, SpansTheFreeBlocksItCrossesGapsIncluded) {
  std::vector<BridgeBlock> blocks{box(Vec3(0, 0.1, 0.5), Vec3(2, 1.2, 1))};
  const Vec3 y = Vec3::UnitY();
  auto extent = free_blocks_along_line(blocks, Vec3(0.2, 0, 0.5), y);
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->first, -0.5, 1e-12);
  EXPECT_NEAR(extent->second, 0.7, 1e-12);
  blocks.push_back(box(Vec3(0, 1.25, 0.5), Vec3(2, 0.5, 1)));
  blocks.push_back(box(Vec3(0, 3, 0.5), Vec3(2, 1, 1), true));
  extent = free_blocks_along_line(blocks, Vec3(0.2, 7, 0.5), y);  // t measured from the origin's y = 7
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->first, -7.5, 1e-12);
  EXPECT_NEAR(extent->second, -5.5, 1e-12);
  EXPECT_FALSE(free_blocks_along_line(blocks, Vec3(0.2, 0, 1.5), y));  // above them all
  // Through the first box's edge at y = 0.7, z = 1, outward both ways: a point.
  EXPECT_FALSE(free_blocks_along_line({blocks[0]}, Vec3(0.2, 0.7, 1.0), Vec3(0, 0.6, -0.8)));
  extent = free_blocks_along_line(blocks, Vec3(1.0, 0, 1.0), y);  // along their top edges: counted
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->first, -0.5, 1e-12);
  EXPECT_NEAR(extent->second, 1.5, 1e-12);
}

// A box of half-widths a (x) and b (y) turned by theta about z: the line x = 0 along y lies in
// it for |y| <= min(a / sin theta, b / cos theta).
TEST(LineThroughBlocks, ATurnedBlocksStretchIsTheClosedForm) {
  const double a = 0.6, b = 0.3;
  for (const double theta : {0.2, 0.7, 1.2}) {
    const Mat3 turn = Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix();
    const std::vector<BridgeBlock> blocks{
        BridgeBlock{transformed(make_box(Vec3::Zero(), Vec3(2 * a, 2 * b, 1)), turn, Vec3::Zero()), Part::imported, 0, false}};
    const double half = std::min(a / std::sin(theta), b / std::cos(theta));
    const auto extent = free_blocks_along_line(blocks, Vec3(0, 0, 0.1), Vec3::UnitY());
    ASSERT_TRUE(extent) << theta;
    EXPECT_NEAR(extent->first, -half, 1e-12) << theta;
    EXPECT_NEAR(extent->second, half, 1e-12) << theta;
  }
}

}  // namespace
}  // namespace ishibashi
