// Joint measures against the kinematics of a block moved by hand: a slide is slip, not a
// crack; a block tipped about an edge opens its joint by a sin(theta) at the far edge; a
// bond lost since the reference cracks its joint; a joint is its original sub-contacts.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/joints.h"
#include "engine/world.h"
#include "scenes.h"

namespace ishibashi {
namespace {

constexpr double kA = 0.64;

TEST(Joints, OneJointPerBlockPairInContactAtTheStart) {
  World w(test::block_on_base(Vec3(kA, kA, kA), test::stone()).build(), 2e-5);
  const Joints j = find_original_joints(w.state());
  ASSERT_EQ(j.size(), 1);
  EXPECT_EQ(j.block_a[0], 0);
  EXPECT_EQ(j.block_b[0], 1);
  EXPECT_EQ(j.point_begin[1], 4);  // the four corners of the bed joint
}

TEST(Joints, SlidingIsSlipNotACrack) {
  World w(test::block_on_base(Vec3(kA, kA, kA), test::stone()).build(), 2e-5);
  Joints j = find_original_joints(w.state());
  w.state().position[1] += Vec3(0.03, 0.04, 0.0);
  const JointCounts c = measure_joints(w.state(), JointThresholds{}, j);
  EXPECT_NEAR(j.slip_m[0], 0.05, 1e-12);
  EXPECT_NEAR(j.opening_m[0], 0.0, 1e-12);
  EXPECT_EQ(c.cracked, 0);
  EXPECT_EQ(c.slipped, 1);
  EXPECT_EQ(c.largest_slip_joint, 0);
}

TEST(Joints, TippingAboutAnEdgeOpensTheFarEdge) {
  World w(test::block_on_base(Vec3(kA, kA, kA), test::stone()).build(), 2e-5);
  State& s = w.state();
  Joints j = find_original_joints(s);
  for (double theta : {0.001, 0.01}) {
    // Rotate about the bed joint's edge x = a/2, z = 0 (axis y): the far edge rises a sin(theta).
    const Quat turn(Eigen::AngleAxisd(theta, Vec3::UnitY()));
    const Vec3 pivot(kA / 2, 0, 0);
    s.position[1] = pivot + turn * (w.model().initial_position[1] - pivot);
    s.orientation[1] = turn * w.model().initial_orientation[1];
    const JointCounts c = measure_joints(s, JointThresholds{}, j);
    EXPECT_NEAR(j.opening_m[0], kA * std::sin(theta), 1e-12) << theta;
    EXPECT_NEAR(j.slip_m[0], 0.5 * kA * (1 - std::cos(theta)), 1e-12) << theta;
    EXPECT_EQ(c.open, kA * std::sin(theta) > 1e-3 ? 1 : 0) << theta;
  }
  // A crack is for good: closing the joint again leaves it cracked, but not open.
  s.position[1] = w.model().initial_position[1];
  s.orientation[1] = w.model().initial_orientation[1];
  const JointCounts c = measure_joints(s, JointThresholds{}, j);
  EXPECT_EQ(c.open, 0);
  EXPECT_EQ(c.cracked, 1);
  // Measured from a new reference (a settled pose), it starts uncracked.
  set_joint_reference(s, j);
  EXPECT_EQ(measure_joints(s, JointThresholds{}, j).cracked, 0);
}

// A joint whose bond breaks is cracked, however little it opens: mortar that failed in
// shear cracks its joint in place. Bonds already broken when the reference is taken (while
// settling) are not this run's cracks.
TEST(Joints, ABondLostSinceTheReferenceCracksTheJointWithoutOpeningIt) {
  World w(test::block_on_base(Vec3(kA, kA, kA), test::stone(1.0, 33.23, 2e5)).build(), 2e-5);
  State& s = w.state();
  Joints j = find_original_joints(s);
  ASSERT_EQ(s.contacts.size(), 4u);
  auto lose_bond = [&s](int i) { s.contacts.flags[i] = SubContactFlag::broken | SubContactFlag::original; };
  lose_bond(0);  // before the reference: settling's
  EXPECT_EQ(set_joint_reference(s, j), 1);
  JointCounts c = measure_joints(s, JointThresholds{}, j);
  EXPECT_EQ(c.cracked, 0);
  lose_bond(1);  // after it
  c = measure_joints(s, JointThresholds{}, j);
  EXPECT_EQ(c.open, 0);
  EXPECT_NEAR(j.opening_m[0], 0.0, 1e-12);
  EXPECT_EQ(c.cracked, 1);
}

// A joint is made of the sub-contacts in contact at the start (flagged original); points a
// stone finds later, as it turns onto another face, are not the joint's.
TEST(Joints, OnlyTheOriginalSubContactsMakeAJoint) {
  World w(test::block_on_base(Vec3(kA, kA, kA), test::stone()).build(), 2e-5);
  State& s = w.state();
  ASSERT_EQ(s.contacts.size(), 4u);
  s.contacts.flags[2] &= ~SubContactFlag::original;
  const Joints j = find_original_joints(s);
  ASSERT_EQ(j.size(), 1);
  EXPECT_EQ(j.point_begin[1], 3);
  for (std::uint8_t& f : s.contacts.flags) f &= ~SubContactFlag::original;
  EXPECT_EQ(find_original_joints(s).size(), 0);
}

}  // namespace
}  // namespace ishibashi
