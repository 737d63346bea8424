// How a run fails, told from stones moved by hand: a stone that fell goes the way of the
// larger horizontal part of its displacement relative to the ground; a part's first fall and
// sides are its stones' earliest fall and where they stood; a ring section hinges
// by the median opening of its joints across the width, not by one joint at its side.
#include <gtest/gtest.h>

#include <vector>

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

// A part's first fall is its earliest stone's, whatever the stones' numbers; a stone's side
// is where it stood across the bridge: within a tenth of the half width of the middle, the
// middle. Three wall stones stand at y = -1, 0.15 and 0.05 m and a fill stone at y = 1 m (the
// bridge spans -1 .. 1: the middle band is +-0.1 m); the walls' fall at 1.0, 1.5 and 1.2 s.
TEST(FallRecord, APartsFirstFallIsItsEarliestAndItsSidesAreWhereTheStonesStood) {
  const Polyhedron slab = make_box(Vec3(0, 0, -0.25), Vec3(8, 8, 0.5));
  std::vector<Polyhedron> stones;
  for (double y : {-1.0, 0.15, 0.05, 1.0}) stones.push_back(make_box(Vec3(0, y, 2), Vec3(0.4, 0.08, 0.4)));
  Model m = test::stones_model({{&slab, Motion::fixed}, {&stones[0], Motion::free}, {&stones[1], Motion::free},
                                {&stones[2], Motion::free}, {&stones[3], Motion::free}});
  for (const auto& [b, part] : {std::pair{0, Part::ground}, {1, Part::wall}, {2, Part::wall}, {3, Part::wall}, {4, Part::fill}})
    m.block_tag[b].part = static_cast<int>(part);
  State s = make_initial_state(m);
  FallRecord falls(m.block_count);
  for (const auto& [time_s, b] : {std::pair{1.0, 1}, {1.2, 3}, {1.5, 2}}) {
    s.time_s = time_s;
    s.position[b] += Vec3(0, 0, -1.5);
    falls.note(m, s, Vec3::Zero());
  }
  const nlohmann::ordered_json how = falls.summary(m, 0.2);
  ASSERT_EQ(how["parts"].size(), 1u) << how.dump();
  const auto& wall = how["parts"][0];
  EXPECT_EQ(wall["fallen"], 3);
  EXPECT_NEAR(wall["first_fall_s"].get<double>(), 0.8, 1e-12);
  EXPECT_EQ(wall["sides"]["-y"], 1);
  EXPECT_EQ(wall["sides"]["middle"], 1);  // y = 0.05
  EXPECT_EQ(wall["sides"]["+y"], 1);      // y = 0.15: beyond the band
}

// A bridge whose ring has three stones of 0.64 m across: three radial joints a section.
struct ThreeAcross {
  BridgeSpec spec;
  Model model;
  Joints joints;
  ThreeAcross() {
    spec.ring.width_m = 1.92;
    spec.ring.voussoirs = 33;
    model = compile_bridge(spec, generate_bridge(spec));
    joints = find_original_joints(World(model, 1e-5).state());
  }
  // The radial joints of section `position` (between ring stones position - 1 and position
  // along the arc; stones of neighbouring rows across that touch along an edge make none).
  std::vector<int> section(int position) const {
    std::vector<int> out;
    for (int j = 0; j < joints.size(); ++j) {
      const BlockTag &a = model.block_tag[joints.block_a[j]], &b = model.block_tag[joints.block_b[j]];
      const int ring = static_cast<int>(Part::ring);
      const bool over_an_area = joints.point_begin[j + 1] - joints.point_begin[j] >= 3;  // not an edge's touch
      if (a.part == ring && b.part == ring && a.course != b.course && std::max(a.course, b.course) == position && over_an_area)
        out.push_back(j);
    }
    return out;
  }
  double hinge_opening_m() const { return 2.0 * kHingeRotationRad * spec.ring.thickness_m; }
};

TEST(RingHinges, ASectionHingesByTheMedianOpeningOfItsJointsAcrossTheWidth) {
  ThreeAcross bridge;
  RingHinges hinges(bridge.model, bridge.joints);
  const std::vector<int> section = bridge.section(10);
  ASSERT_EQ(section.size(), 3u);
  bridge.joints.opening_m[section[0]] = bridge.hinge_opening_m();  // one joint across: the ring's side, not a hinge
  EXPECT_EQ(hinges.note(bridge.joints, 1.0, false), 0);
  bridge.joints.opening_m[section[2]] = bridge.hinge_opening_m();  // two of three: the section has turned
  EXPECT_EQ(hinges.note(bridge.joints, 1.1, false), 1);
}

// A hinge is a section open wider than its neighbours; of two neighbours opened alike (one
// rotation shared by two joints), the first along the arc is the hinge, counted once.
TEST(RingHinges, OfTwoNeighboursOpenedAlikeOneHinges) {
  ThreeAcross bridge;
  RingHinges hinges(bridge.model, bridge.joints);
  for (int position : {10, 11})
    for (int j : bridge.section(position)) bridge.joints.opening_m[j] = bridge.hinge_opening_m();
  EXPECT_EQ(hinges.note(bridge.joints, 1.0, false), 1);
  for (int j : bridge.section(11)) bridge.joints.opening_m[j] *= 1.5;  // now the second is the wider
  EXPECT_EQ(hinges.note(bridge.joints, 1.1, false), 1);
}

}  // namespace
}  // namespace ishibashi
