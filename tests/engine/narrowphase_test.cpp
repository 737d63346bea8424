// Contact geometry: exact overlap areas of offset face-face contacts, and the corner,
// edge and edge-edge configurations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/narrowphase.h"
#include "engine/pipeline.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

// Block 0: unit cube with its top at z = 0 (fixed). Block 1: `top` as given.
State contacts_of(const Polyhedron& top, int subdivision = 1, Model* model_out = nullptr) {
  const Polyhedron bottom = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  const Model m = test::stones_model({{&bottom, Motion::fixed}, {&top, Motion::free}}, {.subdivision = subdivision});
  if (model_out) *model_out = m;
  return test::contacts_found(m);
}

double total_area(const State& s) {
  double a = 0;
  for (double x : s.contacts.area_m2) a += x;
  return a;
}

TEST(Narrowphase, OffsetFaceContactAreaIsExactOverlap) {
  const State s = contacts_of(make_box(Vec3(0.3, 0.4, 0.5), Vec3(1, 1, 1)));
  ASSERT_EQ(s.contacts.size(), 4u);
  EXPECT_NEAR(total_area(s), 0.7 * 0.6, 1e-12);
  for (std::size_t i = 0; i < s.contacts.size(); ++i) {
    EXPECT_NEAR(s.contacts.normal[i].z(), 1.0, 1e-12);
    EXPECT_NEAR(s.contacts.gap_m[i], 0.0, 1e-12);
    EXPECT_NEAR(s.contacts.area_m2[i], 0.42 / 4, 1e-12);  // a rectangle: equal corner shares
  }
}

TEST(Narrowphase, RotatedSquareOverlapIsRegularOctagon) {
  const Mat3 r = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
  const Polyhedron top = transformed(make_box(Vec3::Zero(), Vec3(1, 1, 1)), r, Vec3(0, 0, 0.5));
  const double octagon = 2.0 * (std::sqrt(2.0) - 1.0);
  const State s = contacts_of(top);
  EXPECT_EQ(s.contacts.size(), 8u);
  EXPECT_NEAR(total_area(s), octagon, 1e-12);
  for (int level : {2, 5}) {
    const State sub = contacts_of(top, level);
    EXPECT_EQ(sub.contacts.size(), 8u * level * level);
    EXPECT_NEAR(total_area(sub), octagon, 1e-12) << "subdivision " << level;
  }
}

TEST(Narrowphase, SubdivisionApproachesUniformSpringBed) {
  // The rotational stiffness of a joint is K_n times the second moment of the
  // sub-contact areas about its centre; a uniform bed on a unit square gives 1/12.
  // Corner points give 1/4 (three times too stiff); subdivision must converge to 1/12.
  double last_error = 1e9;
  for (int level : {1, 2, 4, 12}) {
    const State s = contacts_of(make_box(Vec3(0, 0, 0.5), Vec3(1, 1, 1)), level);
    double second = 0;
    for (std::size_t i = 0; i < s.contacts.size(); ++i) second += s.contacts.area_m2[i] * std::pow(s.contacts.point[i].x(), 2);
    const double error = std::abs(second * 12.0 - 1.0);
    if (level == 1) {
      EXPECT_NEAR(second, 0.25, 1e-12);
    }
    EXPECT_LT(error, last_error) << "subdivision " << level;
    last_error = error;
  }
  EXPECT_LT(last_error, 0.01);
}

TEST(Narrowphase, VertexOnFace) {
  // A cube balanced on one corner: rotate so that the body diagonal is vertical.
  const Mat3 r = Eigen::Quaterniond::FromTwoVectors(Vec3(-1, -1, -1).normalized(), -Vec3::UnitZ()).toRotationMatrix();
  const Polyhedron top = transformed(make_box(Vec3::Zero(), Vec3(0.4, 0.4, 0.4)), r, Vec3(0, 0, 0.2 * std::sqrt(3.0)));
  const State s = contacts_of(top);
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_NEAR(s.contacts.point[0].norm(), 0.0, 1e-9);
  EXPECT_NEAR(s.contacts.normal[0].z(), 1.0, 1e-12);
  EXPECT_NEAR(s.contacts.area_m2[0], 0.01 * 0.4 * 0.4, 1e-12);  // nominal: point_area_ratio * size^2
}

TEST(Narrowphase, EdgeOnFace) {
  const Mat3 r = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix();
  const Polyhedron top = transformed(make_box(Vec3::Zero(), Vec3(0.6, 0.4, 0.4)), r, Vec3(0, 0, 0.2 * std::sqrt(2.0)));
  const State s = contacts_of(top);
  ASSERT_EQ(s.contacts.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(std::abs(s.contacts.point[i].x()), 0.3, 1e-9);
    EXPECT_NEAR(s.contacts.point[i].y(), 0.0, 1e-9);
    EXPECT_NEAR(s.contacts.normal[i].z(), 1.0, 1e-12);
  }
}

// Stones of two courses whose plan outlines meet along an edge (F's staggered fill: 2,397
// sub-contacts): the faces touch along a segment, which carries the nominal area in two
// equal shares at its ends, whichever block is a (whose face is the reference) and
// whichever of the reference face's side planes cuts first. Cut from both of its ends, the
// segment once gave its crossing twice: three points, one end with two thirds of the area.
TEST(Narrowphase, FacesMeetingAlongAnEdgeGiveTheSegmentsEndsEqualShares) {
  for (int quarter = 0; quarter < 4; ++quarter)
    for (bool fixed_first : {true, false}) {
      const Mat3 r = Eigen::AngleAxisd(quarter * M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
      // Lower stone x, y in [-0.5, 0.5]; the upper one beside it in y and half over it in x:
      // they touch along y = 0.5, x in [-0.1, 0.5], at z = 0.
      const Polyhedron lower = transformed(make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1)), r, Vec3::Zero());
      const Polyhedron upper = transformed(make_box(Vec3(0.4, 1.0, 0.5), Vec3(1, 1, 1)), r, Vec3::Zero());
      const std::pair<const Polyhedron*, Motion> fixed{&lower, Motion::fixed}, free{&upper, Motion::free};
      const Model m = test::stones_model(fixed_first ? std::vector{fixed, free} : std::vector{free, fixed});
      const State s = test::contacts_found(m);
      const std::string where = "quarter turn " + std::to_string(quarter) + (fixed_first ? ", lower stone a" : ", upper stone a");
      ASSERT_EQ(s.contacts.size(), 2u) << where;
      const Vec3 ends[2] = {r * Vec3(-0.1, 0.5, 0), r * Vec3(0.5, 0.5, 0)};
      const double nominal = m.point_contact_area_m2(0, 1);
      for (int i = 0; i < 2; ++i) {
        const Vec3& x = s.contacts.point[i];
        EXPECT_NEAR(std::min((x - ends[0]).norm(), (x - ends[1]).norm()), 0.0, 1e-9) << where;
        EXPECT_NEAR(s.contacts.area_m2[i], 0.5 * nominal, 1e-15) << where;
      }
      EXPECT_GT((s.contacts.point[0] - s.contacts.point[1]).norm(), 0.5) << where << ": both ends, not one twice";
    }
}

// Two courses of two leaves in running bond on a slab: stones of neighbouring leaves in
// neighbouring courses meet along edges. Numbered forwards or backwards, the stack has the
// same sub-contacts (count, total area) and no two of a pair on one spot: the points a
// joint gets do not depend on which block is a.
TEST(Narrowphase, RunningBondStackHasTheSameContactsWhicheverTheNumbering) {
  std::vector<Polyhedron> stones;
  for (int course = 0; course < 2; ++course)
    for (int leaf = 0; leaf < 2; ++leaf) {
      const bool shifted = course % 2 == 1;  // both leaves alike: a stone meets the other leaf's
                                             // stones of the next course along half its edge
      for (double x : shifted ? std::vector<double>{1.0} : std::vector<double>{0.5, 1.5})
        stones.push_back(make_box(Vec3(x, leaf + 0.5, course + 0.5), Vec3(1, 1, 1)));
    }
  auto contacts = [&](bool backwards) {
    const Polyhedron slab = make_box(Vec3(1, 1, -0.25), Vec3(4, 4, 0.5));
    std::vector<std::pair<const Polyhedron*, Motion>> blocks{{&slab, Motion::fixed}};
    for (std::size_t i = 0; i < stones.size(); ++i)
      blocks.push_back({&stones[backwards ? stones.size() - 1 - i : i], Motion::free});
    State s = test::contacts_found(test::stones_model(blocks));
    for (const Pair& pair : s.pairs)
      for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i)
        for (int j = pair.sub_begin; j < i; ++j)
          EXPECT_GT((s.contacts.point[i] - s.contacts.point[j]).norm(), 1e-9)
              << "pair " << pair.a << "-" << pair.b << (backwards ? " (numbered backwards)" : "") << ": two points on one spot";
    return s;
  };
  const State forwards = contacts(false), backwards = contacts(true);
  EXPECT_EQ(forwards.contacts.size(), backwards.contacts.size());
  EXPECT_NEAR(total_area(forwards), total_area(backwards), 1e-12);
}

// Two stones that meet only along an edge touch four planes at once (each stone's top or
// bottom and its side). The contact normal is the one that points most nearly from one
// centre to the other, whichever stone is a: here the tall stone's centre lies 1.5 m up
// and 1 m across, so the normal is vertical (the one the manifold found depended on which
// stone was a: a's first face of the four, in the block's own face order).
TEST(Narrowphase, StonesMeetingAlongAnEdgeTakeTheNormalFacingTheCentresWhicheverTheNumbering) {
  const Polyhedron low = make_box(Vec3(0, 0, 0.5), Vec3(1, 1, 1)), tall = make_box(Vec3(0, 1, 2), Vec3(1, 1, 2));
  const Polyhedron base = make_box(Vec3(0, 0.5, -0.25), Vec3(4, 4, 0.5));
  for (bool tall_first : {false, true}) {
    const Polyhedron* first = tall_first ? &tall : &low;
    const Polyhedron* second = tall_first ? &low : &tall;
    const State s = test::contacts_found(
        test::stones_model({{&base, Motion::fixed}, {first, Motion::free}, {second, Motion::free}}));
    int between = 0;
    for (const Pair& pair : s.pairs) {
      if (pair.a == 0) continue;  // the base
      for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i, ++between)
        EXPECT_NEAR(std::abs(s.contacts.normal[i].z()), 1.0, 1e-12) << (tall_first ? "tall stone a" : "low stone a");
    }
    EXPECT_EQ(between, 2) << "the edge's two ends";
  }
}

TEST(Narrowphase, EdgeOnEdge) {
  // Two bars turned 45 degrees about their own axes, crossing at right angles: the lower
  // one's top edge runs along x, the upper one's bottom edge along y.
  const double h = 0.1 * std::sqrt(2.0);  // half-diagonal of the 0.2 x 0.2 section
  const Polyhedron lower = transformed(make_box(Vec3::Zero(), Vec3(2, 0.2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix(), Vec3(0, 0, -h));
  const Polyhedron upper = transformed(make_box(Vec3::Zero(), Vec3(0.2, 2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()).toRotationMatrix(), Vec3(0, 0, h - 1e-5));
  const State s = test::contacts_found(test::stones_model({{&lower, Motion::fixed}, {&upper, Motion::free}}));
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_NEAR((s.contacts.point[0] - Vec3(0, 0, -0.5e-5)).norm(), 0.0, 1e-9);  // midway
  EXPECT_NEAR(s.contacts.normal[0].z(), 1.0, 1e-9);
  EXPECT_NEAR(s.contacts.gap_m[0], -1e-5, 1e-12);
  EXPECT_EQ(s.contacts.key[0] >> 62, 2u);  // an edge-edge key
}

TEST(Narrowphase, SeparatedBeyondToleranceHasNoContact) {
  const State s = contacts_of(make_box(Vec3(0, 0, 0.5 + 0.01), Vec3(1, 1, 1)));
  EXPECT_EQ(s.contacts.size(), 0u);
}

// A pair within the broadphase's reach but beyond the tolerance is apart, at the distance
// its separating axis gives, and has no sub-contact: a cube's corner g above a face (the
// face a's, then b's) and two crossed bars' edges g apart, g = 5 tolerances. That
// separation is what lets the search be skipped while b cannot have closed the gap.
TEST(Narrowphase, PairsBeyondTheToleranceAreApartByTheirTrueDistance) {
  const Polyhedron base = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  // A unit cube turned so that a body diagonal stands vertical, its lowest corner g above z = 0.
  const double g = 5e-3;  // 5 tolerances of the cube (1e-3 of its size), 12 of the bars'
  const Mat3 corner_down = (Eigen::AngleAxisd(std::atan(std::sqrt(0.5)), Vec3::UnitY()) *
                            Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX())).toRotationMatrix();
  Polyhedron cube = transformed(make_box(Vec3::Zero(), Vec3(1, 1, 1)), corner_down, Vec3::Zero());
  double lowest = 1e300;
  for (const Vec3& v : cube.vertices) lowest = std::min(lowest, v.z());
  cube = transformed(cube, Mat3::Identity(), Vec3(0, 0, g - lowest));
  const double h = 0.1 * std::sqrt(2.0);  // the crossed bars of EdgeOnEdge, g apart
  const Polyhedron lower = transformed(make_box(Vec3::Zero(), Vec3(2, 0.2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix(), Vec3(0, 0, -h));
  const Polyhedron upper = transformed(make_box(Vec3::Zero(), Vec3(0.2, 2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()).toRotationMatrix(), Vec3(0, 0, h + g));
  struct Case {
    const char* what;
    Model model;
  };
  const Case cases[] = {
      {"a corner above a's face", test::stones_model({{&base, Motion::fixed}, {&cube, Motion::free}})},
      {"a corner above b's face", test::stones_model({{&cube, Motion::free}, {&base, Motion::fixed}})},
      {"crossed edges", test::stones_model({{&lower, Motion::fixed}, {&upper, Motion::free}})},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const State s = test::contacts_found(c.model);
    ASSERT_EQ(s.pairs.size(), 1u);
    EXPECT_LT(c.model.contact_tolerance_m(0, 1), g);
    EXPECT_EQ(s.pairs[0].axis_kind, -1);
    EXPECT_NEAR(s.pairs[0].separation_m, g, 1e-12);
    EXPECT_EQ(s.contacts.size(), 0u);
  }
}

TEST(Narrowphase, KeysPersistWhileSliding) {
  Model m;
  // A 0.6 m block overhanging one edge of the base: two of its own corners and two
  // cuts by the base's edge. Sliding keeps that topology, hence the keys.
  State s = contacts_of(make_box(Vec3(0.45, 0, 0.3), Vec3(0.6, 0.6, 0.6)), 1, &m);
  ASSERT_EQ(s.contacts.size(), 4u);
  const std::vector<std::uint64_t> before = s.contacts.key;
  s.position[1] += Vec3(0.05, 0.02, 0);
  update_pose(m, s);
  update_contacts(m, s, false, 1e-5);
  EXPECT_EQ(s.contacts.key, before);
}

// The narrowphase skips a pair's exact moved test while its bound on the pair's relative
// motion stays below the limit (separating_axis.cpp). The bound must cover the measure the
// exact test takes (b's centroid in a's frame, plus the chord its turn relative to a
// sweeps at b's radius) through random motions of both stones, searches included; and
// both shifted alike, however far, must leave it as it was (the skip is taken).
TEST(Narrowphase, MotionBoundCoversThePairsRelativeMotion) {
  const Polyhedron bottom = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  const Polyhedron top = make_box(Vec3(0.2, 0.1, 0.5), Vec3(1, 1, 1));
  const Model m = test::stones_model({{&bottom, Motion::free}, {&top, Motion::free}});
  State s = test::contacts_found(m);
  ASSERT_EQ(s.pairs.size(), 1u);
  std::mt19937 draw(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto random_vector = [&] { return Vec3(unit(draw), unit(draw), unit(draw)); };
  auto turn = [](const Vec3& v) { return Quat(Eigen::AngleAxisd(v.norm(), v.normalized())); };
  const double limit = 0.05 * m.contact_tolerance_m(0, 1);
  int searches = 0;
  for (int step = 0; step < 600; ++step) {
    const bool rigid = step % 3 == 0;  // both stones shifted alike, 20 times the limit
    const Vec3 common_shift = 1e-3 * random_vector();
    for (int b : {0, 1}) {
      if (rigid) {
        s.position[b] += common_shift;
      } else {
        s.position[b] += 1e-5 * random_vector();
        s.orientation[b] = (turn(1e-5 * random_vector()) * s.orientation[b]).normalized();
      }
    }
    const Pair before = s.pairs[0];
    update_pose(m, s);
    update_contacts(m, s, false, 1e-5);
    const Pair& pair = s.pairs[0];
    if (pair.offset_at_search != before.offset_at_search) ++searches;
    const Vec3 offset = s.orientation[0].toRotationMatrix().transpose() * (s.position[1] - s.position[0]);
    const Quat relative = s.orientation[0].conjugate() * s.orientation[1];
    const Eigen::Vector4d q0 = pair.relative_at_search.coeffs(), q = relative.coeffs();
    const double half_turn = 2 * std::asin(0.5 * std::min((q0 - q).norm(), (q0 + q).norm()));
    const double measure = (offset - pair.offset_at_search).norm() + 2 * m.radius_m[1] * std::sin(half_turn);
    // Within the exact test's own rounding (its chord's root of 1 - cos^2 near 0: about 1e-8 m).
    ASSERT_GE(pair.moved_bound_m, measure - 1e-7) << "step " << step;
    if (rigid && pair.offset_at_search == before.offset_at_search) {  // skipped: added only its slack
      EXPECT_LT(pair.moved_bound_m - before.moved_bound_m, 1e-6 * limit) << "step " << step;
    }
  }
  EXPECT_GT(searches, 10);  // the random motions crossed the limit again and again
}

// A face pair whose manifold came out empty is not clipped again while no point of the
// incident stone can reach the face's plane (separating_axis.cpp): until then a clip could
// give only open points, which carry no force. A stone next to the base's top face walks
// over its edge (the clip's slack is 0.1 of the tolerance T) and down onto it, beside a
// copy clipped every step as before: every closed point (gap <= 0) must be the same in
// both, step by step; only open points may be missing.
struct ClearWalk {
  int steps_skipped = 0;  // not clipped
  int steps_open_left_out = 0, steps_touching = 0;
  bool closed_differ = false;
};

// `stone` (0 or 1, the other the base) starts at `start` (in T) from beside the base, then
// moves each step by the next of `shifts` (in T) and up to `noise` (in T, and as much of a
// turn at the corners of the block that turns: the stone, or the base when `base_turns`,
// which moves the stone's far corners relative to the base's face by more than the base's
// own corners move).
ClearWalk walk_onto_face(const Model& m, int stone, const Vec3& start, const std::vector<Vec3>& shifts, double noise,
                         std::mt19937& draw, bool base_turns = false) {
  const double tol = m.contact_tolerance_m(0, 1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto random_vector = [&] { return Vec3(unit(draw), unit(draw), unit(draw)); };
  State rule = make_initial_state(m);
  rule.position[stone] += tol * start;
  update_pose(m, rule);
  update_pairs(m, rule);
  update_contacts(m, rule, true, 1e-5);
  EXPECT_EQ(rule.pairs.size(), 1u);
  State every_step = rule;
  auto closed = [](const State& s) {
    std::vector<std::pair<std::uint64_t, double>> points;
    for (int i = 0; i < static_cast<int>(s.contacts.size()); ++i)
      if (s.contacts.gap_m[i] <= 0) points.push_back({s.contacts.key[i], s.contacts.gap_m[i]});
    std::sort(points.begin(), points.end());
    return points;
  };
  ClearWalk w;
  for (int step = 0; step < static_cast<int>(shifts.size()); ++step) {
    const Vec3 shift = tol * (shifts[step] + noise * random_vector());
    const int turner = base_turns ? 1 - stone : stone;
    const Vec3 turn = tol * noise / m.radius_m[turner] * random_vector();
    for (State* s : {&rule, &every_step}) {
      s->position[stone] += shift;
      s->orientation[turner] = (Quat(Eigen::AngleAxisd(turn.norm(), turn.normalized())) * s->orientation[turner]).normalized();
      update_pose(m, *s);
    }
    every_step.pairs[0].clear_for_m = 0.0;
    // Whether this step clips the pair (pair_manifold on a copy: true when it makes a manifold).
    const Pair before = rule.pairs[0];
    Pair probe = before;
    PairWorld world;
    Manifold manifold;
    w.steps_skipped += !pair_manifold(m, rule, probe, world, manifold) && before.sub_count == 0 &&
                       (before.axis_kind == 0 || before.axis_kind == 1);
    update_contacts(m, rule, false, 1e-5);
    update_contacts(m, every_step, false, 1e-5);
    if (closed(rule) != closed(every_step)) {
      ADD_FAILURE() << "the closed points differ at step " << step << " (the stone at " << rule.position[stone].transpose() / tol << " T)";
      w.closed_differ = true;
      break;
    }
    w.steps_open_left_out += every_step.contacts.size() > rule.contacts.size();
    w.steps_touching += !closed(rule).empty();
  }
  return w;
}

TEST(Narrowphase, EmptyFaceManifoldIsNotClippedWhileTheStoneCannotReachThePlane) {
  const Polyhedron base = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  const Polyhedron beside = make_box(Vec3(1, 0, 0.5), Vec3(1, 1, 1));
  const Model base_first = test::stones_model({{&base, Motion::fixed}, {&beside, Motion::free}});
  const double tol = base_first.contact_tolerance_m(0, 1);
  {
    // 0.2 T beyond the edge and 0.4 T above the plane: the base's top face, no point.
    State s = test::contacts_found(base_first);
    s.position[1] += Vec3(0.2 * tol, 0, 0.4 * tol);
    update_pose(base_first, s);
    update_contacts(base_first, s, true, 1e-5);
    ASSERT_EQ(s.pairs[0].axis_kind, 0);
    ASSERT_EQ(s.contacts.size(), 0u);
    // Clear until it has moved by 0.4 T less the reserve (0.1 T).
    EXPECT_NEAR(s.pairs[0].clear_for_m, 0.3 * tol, 1e-9 * tol);
    // Damping::capped sets its caps from open points too: the rule is off.
    const Model capped = test::stones_model({{&base, Motion::fixed}, {&beside, Motion::free}}, {.damping = Damping::capped});
    State c = test::contacts_found(capped);
    c.position[1] = s.position[1];
    update_pose(capped, c);
    update_contacts(capped, c, true, 1e-5);
    EXPECT_EQ(c.pairs[0].clear_for_m, 0.0);
  }
  {
    // Beside the face: the top face kept by its hysteresis (0.05 T above the plane, 0.12 T
    // beyond the edge; the side face's 0.12 T is within 0.1 T of it), the stone 0.02 T
    // beyond the clip's slack: no clip gives it anything while it stays beyond.
    State s = test::contacts_found(base_first);
    s.position[1] += Vec3(0.2 * tol, 0, 0.4 * tol);
    update_pose(base_first, s);
    update_contacts(base_first, s, true, 1e-5);
    auto move_by = [&](const Vec3& shift) {
      s.position[1] += tol * shift;
      update_pose(base_first, s);
      Pair probe = s.pairs[0];
      PairWorld world;
      Manifold manifold;
      const bool clipped = pair_manifold(base_first, s, probe, world, manifold);
      update_contacts(base_first, s, false, 1e-5);
      return clipped;
    };
    EXPECT_TRUE(move_by(Vec3(-0.08, 0, -0.35)));  // searched again
    ASSERT_EQ(s.pairs[0].axis_kind, 0);
    ASSERT_EQ(s.contacts.size(), 0u);
    // Too low for the plane's rule (0.05 T < its reserve), beside by 0.02 T.
    EXPECT_GE(s.pairs[0].beside_axis, 0);
    EXPECT_NEAR(s.pairs[0].clear_for_m, 0.02 * tol, 1e-5 * tol);
    // Along the edge by 0.03 T (past its 0.02 T, within the search's 0.05 T): checked
    // again, still beside by 0.02 T, not clipped. Then 0.015 T toward it: within what that
    // allows. Another 0.01 T: checked, within the slack, clipped.
    EXPECT_FALSE(move_by(Vec3(0, 0.03, 0)));
    EXPECT_NEAR(s.pairs[0].clear_for_m, 0.02 * tol, 1e-5 * tol);
    EXPECT_FALSE(move_by(Vec3(-0.015, 0, 0)));
    EXPECT_NEAR(s.pairs[0].clear_for_m, 0.005 * tol, 1e-5 * tol);
    EXPECT_TRUE(move_by(Vec3(-0.01, 0, 0)));
    EXPECT_GT(s.contacts.size(), 0u);  // open points over the face's edge
  }
  std::mt19937 draw(11);
  // Slid over the face and down onto it: most steps skipped while it is beside the face,
  // open points left out over it, then closed ones.
  const ClearWalk slide = walk_onto_face(base_first, 1, Vec3(0.2, 0, 0.4), std::vector<Vec3>(300, Vec3(-0.003, 0, -0.002)), 0.0, draw);
  EXPECT_GT(slide.steps_skipped, 30);
  EXPECT_GT(slide.steps_open_left_out, 0);
  EXPECT_GT(slide.steps_touching, 50);
  // The closest call: the top face kept by its hysteresis with the stone just beyond the
  // slack (0.12 T) and 0.03 T above the plane, then over the edge and 0.005 T into the face
  // within one search's limit (0.043 of the 0.05 T): clear of the plane for less than the
  // reserve, it is skipped only while it is beside the face, 0.02 T beyond the slack at
  // first (0.012 T a step by the bound's 1-norm): one step, a second after a check (0.01 T
  // beyond), a third (0.005 T), then clipped.
  std::vector<Vec3> closest(1, Vec3(0, 0, -0.17));
  closest.insert(closest.end(), 5, Vec3(-0.005, 0, -0.007));
  const ClearWalk close_call = walk_onto_face(base_first, 1, Vec3(0.12, 0, 0.2), closest, 0.0, draw);
  EXPECT_EQ(close_call.steps_skipped, 3);
  EXPECT_GT(close_call.steps_touching, 0);
  // Random walks down across the edge, turning, with the base's face as a's (kind 0) or b's
  // (kind 1: the stone's points move with its lever about the base's centre); in the last
  // twenty the base turns, not the stone.
  const Model base_second = test::stones_model({{&beside, Motion::free}, {&base, Motion::fixed}});
  std::uniform_real_distribution<double> share(0.0, 1.0);
  int skipped = 0, touching = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const bool second = trial % 2 == 1;
    const Vec3 start(0.1 + 0.25 * share(draw), 0.3 * share(draw), 0.05 + 0.4 * share(draw));
    const ClearWalk w = walk_onto_face(second ? base_second : base_first, second ? 0 : 1, start,
                                       std::vector<Vec3>(200, Vec3(-0.002, 0, -0.003)), 0.003, draw, trial >= 40);
    skipped += w.steps_skipped;
    touching += w.steps_touching;
    if (w.closed_differ) break;
  }
  EXPECT_GT(skipped, 200);
  EXPECT_GT(touching, 200);
}

// A 60-gon (the most corners a face may have) on the cube at the finest subdivision:
// 60 fan triangles x 16^2 = 15,360 points, past the manifold's first 4,096. Every point
// is kept: together they carry the whole polygon's area.
TEST(Narrowphase, ManifoldGrowsBeyondItsFirstCapacityInsteadOfDroppingPoints) {
  std::vector<Vec3> base;
  const double r = 0.45;
  for (int k = 0; k < kMaxFaceCorners; ++k) {
    const double t = 2 * M_PI * k / kMaxFaceCorners;
    base.push_back(Vec3(r * std::cos(t), r * std::sin(t), 0));
  }
  const State s = contacts_of(make_prism(base, 0.0, 0.5), kMaxSubdivision);
  EXPECT_EQ(s.contacts.size(), static_cast<std::size_t>(kMaxFaceCorners * kMaxSubdivision * kMaxSubdivision));
  const double polygon_area = 0.5 * kMaxFaceCorners * r * r * std::sin(2 * M_PI / kMaxFaceCorners);
  EXPECT_NEAR(total_area(s), polygon_area, 1e-9 * polygon_area);
}

// A face with more corners than the narrowphase's fixed polygon buffers allow is refused
// when the block is added, naming the block and the face.
TEST(Narrowphase, FaceWithTooManyCornersIsRefusedByName) {
  std::vector<Vec3> base;
  for (int k = 0; k <= kMaxFaceCorners; ++k) {
    const double t = 2 * M_PI * k / (kMaxFaceCorners + 1);
    base.push_back(Vec3(std::cos(t), std::sin(t), 0));
  }
  const Polyhedron p = make_prism(base, 0.0, 1.0);
  ModelBuilder b;
  const int mat = b.add_material(test::stone());
  try {
    b.add_block(p.vertices, p.faces, mat, Motion::free, "disc");
    FAIL() << "a 61-corner face was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("block 0 'disc'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("has 61 corners; at most 60"), std::string::npos) << e.what();
  }
}

// An irregular pentagon (m, counter-clockwise in the plane z = 0): a prism on it stands on the base.
const std::vector<Vec3> kPentagon{{-0.40, -0.30, 0}, {0.35, -0.42, 0}, {0.44, 0.10, 0}, {0.05, 0.41, 0}, {-0.38, 0.22, 0}};

// JointRule::moments on an irregular convex pentagon lying on the cube: the sub-contacts'
// areas, first and second moments are the polygon's (exact polygon formulas), and every
// corner of the polygon keeps a point.
TEST(Narrowphase, MomentRuleCarriesThePolygonsAreaCentroidAndSecondMoments) {
  const std::vector<Vec3>& base = kPentagon;
  const Polyhedron bottom = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  const Polyhedron top = make_prism(base, 0.0, 0.3);
  const State s = test::contacts_found(
      test::stones_model({{&bottom, Motion::fixed}, {&top, Motion::free}}, {.joint_rule = JointRule::moments}));
  ASSERT_EQ(s.contacts.size(), 2 * base.size() + 1);
  // Exact moments of the polygon (Green's theorem): area, int x, int y, int x^2, int y^2, int x y.
  double area = 0, mx = 0, my = 0, ixx = 0, iyy = 0, ixy = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const Vec3& p = base[i];
    const Vec3& q = base[(i + 1) % base.size()];
    const double cross = p.x() * q.y() - q.x() * p.y();
    area += cross / 2;
    mx += (p.x() + q.x()) * cross / 6;
    my += (p.y() + q.y()) * cross / 6;
    ixx += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * cross / 12;
    iyy += (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) * cross / 12;
    ixy += (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) * cross / 24;
  }
  double w = 0, wx = 0, wy = 0, wxx = 0, wyy = 0, wxy = 0;
  const SubContacts& c = s.contacts;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double x = c.point[i].x(), y = c.point[i].y(), a = c.area_m2[i];
    w += a, wx += a * x, wy += a * y, wxx += a * x * x, wyy += a * y * y, wxy += a * x * y;
  }
  EXPECT_NEAR(w, area, 1e-12);
  EXPECT_NEAR(wx, mx, 1e-12);
  EXPECT_NEAR(wy, my, 1e-12);
  EXPECT_NEAR(wxx, ixx, 1e-12);
  EXPECT_NEAR(wyy, iyy, 1e-12);
  EXPECT_NEAR(wxy, ixy, 1e-12);
  for (const Vec3& corner : base) {
    bool found = false;
    for (std::size_t i = 0; i < c.size(); ++i) found = found || (c.point[i] - corner).norm() < 1e-12;
    EXPECT_TRUE(found) << "no point at the corner " << corner.transpose();
  }
}

// Every point of a face-face manifold has the gap of the incident face over the reference
// plane where it stands, and stands midway between the two: a prism tilted by 1e-4 rad
// about x and pressed 20 um into the base has the gap y tan(1e-4) - 20 um at (x, y), for
// the corner rule's points, the moment rule's (corners, centroid and fan triangles'
// centroids: those away from the corners take their gap from the incident face's plane)
// and a subdivision's (sub-triangles' centroids).
TEST(Narrowphase, EveryPointHasTheIncidentFacesGapWhereItStands) {
  const std::vector<Vec3>& outline = kPentagon;
  const double tilt = 1e-4, pressed = 2e-5;  // rad, m
  const Polyhedron bottom = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1));
  const Polyhedron top = transformed(make_prism(outline, 0.0, 0.3), Eigen::AngleAxisd(tilt, Vec3::UnitX()).toRotationMatrix(),
                                     Vec3(0, 0, -pressed));
  const struct {
    const char* what;
    ModelOptions options;
    std::size_t points;
  } rules[] = {{"corners", {.joint_rule = JointRule::corners}, outline.size()},
               {"moments", {.joint_rule = JointRule::moments}, 2 * outline.size() + 1},
               {"subdivision 2", {.subdivision = 2}, 4 * outline.size()}};
  for (const auto& rule : rules) {
    SCOPED_TRACE(rule.what);
    const State s = test::contacts_found(test::stones_model({{&bottom, Motion::fixed}, {&top, Motion::free}}, rule.options));
    const SubContacts& c = s.contacts;
    ASSERT_EQ(c.size(), rule.points);
    double lowest = 0, highest = -1;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const double gap = c.point[i].y() * std::tan(tilt) - pressed;
      EXPECT_NEAR(c.gap_m[i], gap, 1e-13) << "point " << i << " at " << c.point[i].transpose();
      EXPECT_NEAR(c.point[i].z(), 0.5 * gap, 1e-13) << "point " << i;
      EXPECT_NEAR(c.normal[i].z(), 1.0, 1e-12);
      lowest = std::min(lowest, c.gap_m[i]), highest = std::max(highest, c.gap_m[i]);
    }
    EXPECT_LT(lowest, -5e-5);  // the gaps span the tilt: the check is not of a flat joint
    EXPECT_GT(highest, 1e-5);
  }
}

// Every pair's range lies within the arrays, no two overlap, and the entries outside them
// are exactly the dead ones counted.
void expect_ranges_consistent(const State& s) {
  std::vector<std::uint8_t> used(s.contacts.size(), 0);
  int live = 0;
  for (const Pair& pair : s.pairs) {
    ASSERT_GE(pair.sub_begin, 0);
    ASSERT_LE(pair.sub_begin + pair.sub_count, static_cast<int>(s.contacts.size()));
    for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
      ASSERT_EQ(used[i], 0) << "two pairs share sub-contact " << i;
      used[i] = 1;
      ++live;
    }
  }
  EXPECT_EQ(static_cast<int>(s.contacts.size()) - live, s.contacts_dead);
}

// A pair that gains or loses sub-contacts gets a new range after the arrays' end and
// leaves its old one dead, until a compaction lays the arrays out densely again. Where the
// sub-contacts lie must change nothing: a shaken wall stepped with that layout and the
// same wall laid out densely after every step keep every sub-contact and every block
// bit for bit, step after step.
TEST(Narrowphase, AppendedRangesStepExactlyAsADenseLayout) {
  WallSpec spec;
  spec.courses = 5;
  spec.stones_per_course = 14;
  spec.leaves = 2;
  World appended(make_wall_model(spec), 1e-5), dense(make_wall_model(spec), 1e-5);
  int sparse_steps = 0;  // steps that ended with dead entries in the appended layout
  for (int i = 0; i < 1500; ++i) {
    for (World* w : {&appended, &dense}) {
      State& s = w->state();
      s.velocity[0].x() += 0.8 * 9.81 * std::sin(2 * M_PI * 5.0 * s.time_s) * w->dt_s();
      w->step();
    }
    compact_contacts(dense.model(), dense.state());
    ASSERT_EQ(dense.state().contacts_dead, 0);
    sparse_steps += appended.state().contacts_dead > 0;
    expect_ranges_consistent(appended.state());
    ASSERT_EQ(appended.state_hash(), dense.state_hash()) << "step " << i;
  }
  EXPECT_GE(sparse_steps, 100) << "steps with dead entries: the appended layout was hardly exercised";
  // Every field of every sub-contact, in pair order, the same bytes.
  const State &a = appended.state(), &d = dense.state();
  ASSERT_EQ(sub_contact_count(a), sub_contact_count(d));
  std::vector<int> order_a, order_d;
  for_each_sub_contact(a, [&](int i) { order_a.push_back(i); });
  for_each_sub_contact(d, [&](int i) { order_d.push_back(i); });
  for (std::size_t k = 0; k < order_a.size(); ++k) {
    std::vector<std::string> bytes_a, bytes_d;
    a.contacts.for_each_array([&](const auto& array) {
      bytes_a.emplace_back(reinterpret_cast<const char*>(&array[order_a[k]]), sizeof(array[0]));
    });
    d.contacts.for_each_array([&](const auto& array) {
      bytes_d.emplace_back(reinterpret_cast<const char*>(&array[order_d[k]]), sizeof(array[0]));
    });
    ASSERT_EQ(bytes_a, bytes_d) << "sub-contact " << k << " in pair order";
  }
}

}  // namespace
}  // namespace ishibashi
