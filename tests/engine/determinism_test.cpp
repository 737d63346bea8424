// Results do not depend on the number of threads: bit-identical states.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "engine/world.h"
#include "geometry/demo_scenes.h"

namespace ishibashi {
namespace {

std::uint64_t shaken_wall_hash(int threads) {
  omp_set_num_threads(threads);
  WallSpec spec;
  spec.courses = 5;
  spec.stones_per_course = 14;  // 141 blocks: enough for the loops to run on threads
  spec.leaves = 2;
  World w(make_wall_model(spec), 1e-5);
  State& s = w.state();
  for (int i = 0; i < 3000; ++i) {
    s.velocity[0].x() += 0.8 * 9.81 * std::sin(2 * M_PI * 5.0 * s.time_s) * w.dt_s();
    w.step();
  }
  EXPECT_GT(s.contacts.size(), 100u);
  return w.state_hash();
}

TEST(Determinism, SameStateHashForOneToFourThreads) {
  const int saved = omp_get_max_threads();
  const std::uint64_t one = shaken_wall_hash(1);
  for (int threads : {2, 3, 4}) EXPECT_EQ(shaken_wall_hash(threads), one) << threads << " threads";
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace ishibashi
