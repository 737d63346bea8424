// The cell-list broadphase against the brute-force oracle on random scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "engine/pipeline.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

std::vector<std::pair<int, int>> as_pairs(const std::vector<Pair>& p) {
  std::vector<std::pair<int, int>> out;
  for (const Pair& q : p) out.emplace_back(q.a, q.b);
  return out;
}

TEST(Broadphase, MatchesBruteForceOnRandomScenes) {
  for (int seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    ModelBuilder b;
    const int mat = b.add_material(test::stone());
    const int n = 300;
    for (int i = 0; i < n; ++i) {
      const Vec3 size(0.1 + 0.9 * u(rng), 0.1 + 0.9 * u(rng), 0.1 + 0.9 * u(rng));
      const Vec3 c(20 * u(rng), 20 * u(rng), 5 * u(rng));
      const Mat3 r = Eigen::AngleAxisd(6.28 * u(rng), Vec3(u(rng), u(rng), u(rng) + 0.1).normalized()).toRotationMatrix();
      const Polyhedron p = transformed(make_box(Vec3::Zero(), size), r, c);
      b.add_block(p.vertices, p.faces, mat, u(rng) < 0.1 ? Motion::fixed : Motion::free);
    }
    const Model m = b.build();
    State s = make_initial_state(m);
    ASSERT_TRUE(update_pairs(m, s));
    const auto oracle = brute_force_pairs(m, s);
    EXPECT_GT(oracle.size(), 50u);
    EXPECT_EQ(as_pairs(s.pairs), as_pairs(oracle)) << "seed " << seed;

    // Each block on its own by just under half the margin, the most it moves before a
    // rebuild: every two blocks whose spheres then overlap (which may touch) are listed
    // already. The margin inflates each sphere by half of it.
    const std::vector<Vec3> placed = s.position;
    for (int i = 0; i < n; ++i) s.position[i] += 0.49 * m.margin_m * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    EXPECT_FALSE(update_pairs(m, s));
    const auto listed = as_pairs(s.pairs);
    int may_touch = 0;
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if ((m.motion[a] == Motion::free || m.motion[b] == Motion::free) &&
            (s.position[a] - s.position[b]).norm() < m.radius_m[a] + m.radius_m[b]) {
          ++may_touch;
          EXPECT_TRUE(std::binary_search(listed.begin(), listed.end(), std::make_pair(a, b))) << a << "-" << b << ", seed " << seed;
        }
    EXPECT_GT(may_touch, 40);
    s.position = placed;

    // Move every block a little: below half the margin, no rebuild; beyond it, a
    // rebuild that again equals the oracle.
    for (int i = 0; i < n; ++i) s.position[i] += Vec3(0.3 * m.margin_m, 0, 0);
    EXPECT_FALSE(update_pairs(m, s));
    for (int i = 0; i < n; ++i) s.position[i] += Vec3(3 * (u(rng) - 0.5), 3 * (u(rng) - 0.5), 0);
    ASSERT_TRUE(update_pairs(m, s));
    EXPECT_EQ(as_pairs(s.pairs), as_pairs(brute_force_pairs(m, s))) << "seed " << seed;
  }
}

// Blocks on a ground slab far larger than they are, beside a long fixed wall, with small
// fixed blocks among them; the wall comes before the free blocks, the ground after. The
// wall and the ground stay out of the grid, whose cells the free blocks size, and every
// pair the oracle finds is still found.
TEST(Broadphase, LargeImmobileBlocksStayOutOfTheGrid) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ModelBuilder b;
  const int mat = b.add_material(test::stone());
  auto add_box = [&](const Vec3& centre, const Vec3& size, Motion motion) {
    const Polyhedron p = make_box(centre, size);
    return b.add_block(p.vertices, p.faces, mat, motion);
  };
  const int wall = add_box(Vec3(10, -1, 2), Vec3(20, 0.5, 4), Motion::fixed);  // a fixed wall along the scene
  for (int i = 0; i < 400; ++i) {
    const bool fixed = u(rng) < 0.1;  // small fixed blocks, no larger than the free ones: in the grid
    const Vec3 size = (fixed ? 0.5 : 1.0) * Vec3(0.2 + 0.5 * u(rng), 0.2 + 0.5 * u(rng), 0.2 + 0.5 * u(rng));
    add_box(Vec3(20 * u(rng), 4 * u(rng) - 0.5, 0.1 + 3 * u(rng)), size, fixed ? Motion::fixed : Motion::free);
  }
  const int ground = add_box(Vec3(10, 0, -0.25), Vec3(60, 40, 0.5), Motion::fixed);
  const Model m = b.build();
  State s = make_initial_state(m);
  ASSERT_TRUE(update_pairs(m, s));
  EXPECT_EQ(s.large_block, (std::vector<int>{wall, ground}));
  const auto oracle = brute_force_pairs(m, s);
  int with_ground = 0, with_wall = 0;
  for (const Pair& p : oracle) {
    with_ground += p.b == ground;
    with_wall += p.a == wall;
  }
  EXPECT_GT(with_ground, 50);
  EXPECT_GT(with_wall, 10);
  EXPECT_EQ(as_pairs(s.pairs), as_pairs(oracle));
}

// Slabs 0.5 x 0.5 m side by side: 0.2 mm thick (a ring cut by stone_m in millimetres) each
// sphere holds every other slab's centre, two million pairs, and the model is refused,
// naming a slab, before the pair list is made; 5 cm thick, about 28 a slab, it passes.
TEST(Broadphase, CrowdedSpheresAreRefusedBeforeThePairList) {
  auto slabs = [](double thickness) {
    ModelBuilder b;
    const int mat = b.add_material(test::stone());
    for (int i = 0; i < 2000; ++i) {
      const Polyhedron p = make_box(Vec3(0, i * thickness, 0.25), Vec3(0.5, thickness, 0.5));
      b.add_block(p.vertices, p.faces, mat, Motion::free);
    }
    return b.build();
  };
  const Model thin = slabs(2e-4);
  State s = make_initial_state(thin);
  try {
    refuse_crowded_spheres(thin, s);
    ADD_FAILURE() << "2,000 slabs 0.2 mm thick were accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("bounding spheres overlap in more than 1000000 pairs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("block "), std::string::npos) << e.what();
  }
  EXPECT_TRUE(s.pairs.empty());
  const Model thick = slabs(0.05);
  State t = make_initial_state(thick);
  EXPECT_NO_THROW(refuse_crowded_spheres(thick, t));
  ASSERT_TRUE(update_pairs(thick, t));
  EXPECT_LT(t.pairs.size(), 100u * 2000u);
}

// Stones thrown absurdly far (a hand-made checkpoint's) have cells of their own at the grid's
// edge: without the clamp their cell index overflows int64 (UBSan's float-cast-overflow, in
// the sanitizer build), and two far out in one cell are still no pair.
TEST(Broadphase, StonesFarOutOfRangeGetACellAndNoPartners) {
  ModelBuilder b;
  const int mat = b.add_material(test::stone());
  for (int i = 0; i < 5; ++i) {
    const Polyhedron p = make_box(Vec3(i, 0, 0.5), Vec3(1, 1, 1));
    b.add_block(p.vertices, p.faces, mat, Motion::free);
  }
  const Model m = b.build();
  State s = make_initial_state(m);
  s.position[2] = Vec3(1e293, 0, 0);
  s.position[3] = Vec3(2e293, 0, 0);
  s.position[4] = Vec3(-1e300, 5, 1e300);
  update_pairs(m, s);
  EXPECT_EQ(as_pairs(s.pairs), (std::vector<std::pair<int, int>>{{0, 1}}));
}

}  // namespace
}  // namespace ishibashi
