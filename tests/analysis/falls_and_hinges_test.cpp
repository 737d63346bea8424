// How a run fails, told from stones moved by hand: a stone that fell goes the way of the
// larger horizontal part of its displacement relative to the ground; a ring section hinges
// by the median opening of its joints across the width, not by one joint at its side.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "analysis/run/how_it_fails.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "scenes.h"

namespace ishibashi {
namespace {

// A stone dropped by hand 1 m (more than its size: fallen) and moved sideways by `sideways`,
// the ground displaced by `ground`: which way the record says it fell.
std::string fell_toward(const Vec3& sideways, const Vec3& ground) {
  const Model m = test::block_on_base(Vec3(0.4, 0.4, 0.4), test::stone()).build();
  State s = make_initial_state(m);
  s.position[1] += sideways + Vec3(0, 0, -1.0);
  FallRecord record(m.block_count);
  record.note(m, s, ground);
  const nlohmann::ordered_json how = record.summary(m, 0.0);
  for (const char* way : {"+x", "-x", "+y", "-y"})
    if (how["toward"][way] == 1) return way;
  return "none";
}

TEST(FallRecord, AStoneFallsTheWayOfTheLargerHorizontalPartOfItsDisplacementFromTheGround) {
  EXPECT_EQ(fell_toward(Vec3(0.30, 0.20, 0), Vec3::Zero()), "+x");
  EXPECT_EQ(fell_toward(Vec3(0.20, -0.30, 0), Vec3::Zero()), "-y");
  EXPECT_EQ(fell_toward(Vec3(-0.30, 0.29, 0), Vec3::Zero()), "-x");
  EXPECT_EQ(fell_toward(Vec3(0.30, 0.20, 0), Vec3(0.40, 0, 0)), "+y");  // it went 0.1 m less far than the ground along x
}

TEST(RingHinges, ASectionHingesByTheMedianOpeningOfItsJointsAcrossTheWidth) {
  BridgeSpec spec;
  spec.ring.width_m = 1.92;  // three stones of 0.64 m across: three radial joints a section
  spec.ring.voussoirs = 33;
  const Model m = compile_bridge(spec, generate_bridge(spec));
  World w(m, 1e-5);
  Joints joints = find_original_joints(w.state());
  RingHinges hinges(m, joints);
  // The radial joints of section 10 (between ring stones 9 and 10 along the arc; stones of
  // neighbouring rows across that touch along an edge make none).
  std::vector<int> section;
  for (int j = 0; j < joints.size(); ++j) {
    const BlockTag &a = m.block_tag[joints.block_a[j]], &b = m.block_tag[joints.block_b[j]];
    const int ring = static_cast<int>(Part::ring);
    const bool over_an_area = joints.point_begin[j + 1] - joints.point_begin[j] >= 3;  // not an edge's touch
    if (a.part == ring && b.part == ring && a.course != b.course && std::max(a.course, b.course) == 10 && over_an_area)
      section.push_back(j);
  }
  ASSERT_EQ(section.size(), 3u);
  const double hinge = 2.0 * kHingeRotationRad * spec.ring.thickness_m;
  joints.opening_m[section[0]] = hinge;  // one joint across: the ring's side, not a hinge
  EXPECT_EQ(hinges.note(joints, 1.0, false), 0);
  joints.opening_m[section[2]] = hinge;  // two of three: the section has turned
  EXPECT_EQ(hinges.note(joints, 1.1, false), 1);
}

}  // namespace
}  // namespace ishibashi
