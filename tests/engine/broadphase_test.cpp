// The cell-list broadphase against the brute-force oracle on random scenes.
#include <gtest/gtest.h>

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

    // Move every block a little: below half the margin, no rebuild; beyond it, a
    // rebuild that again equals the oracle.
    for (int i = 0; i < n; ++i) s.position[i] += Vec3(0.3 * m.margin_m, 0, 0);
    EXPECT_FALSE(update_pairs(m, s));
    for (int i = 0; i < n; ++i) s.position[i] += Vec3(3 * (u(rng) - 0.5), 3 * (u(rng) - 0.5), 0);
    ASSERT_TRUE(update_pairs(m, s));
    EXPECT_EQ(as_pairs(s.pairs), as_pairs(brute_force_pairs(m, s))) << "seed " << seed;
  }
}

}  // namespace
}  // namespace ishibashi
