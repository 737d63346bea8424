// The pose a step's integrate pass makes for the next step (pose.cpp, integrate.cpp) is the
// pose stage's own, a block moved between steps is posed where it is, and the motion bounds
// add up until a narrowphase reads them.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>

#include "engine/pipeline.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"

namespace ishibashi {
namespace {

World shaken_wall(Damping damping, int threads) {
  omp_set_num_threads(threads);
  WallSpec spec;
  spec.courses = 4;
  spec.stones_per_course = 8;
  spec.options.damping = damping;
  return World(make_wall_model(spec), damping == Damping::implicit ? 3e-5 : 1e-5);
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(T) * a.size()) == 0;
}

// After every step the rotations and world face planes equal, bit for bit, those the pose
// stage makes from the blocks' orientations and positions, and so does the broadphase's
// check; with explicit and implicit dashpots, on one thread and on three.
TEST(Pose, EachStepLeavesThePoseOfWhereTheBlocksAre) {
  const int saved = omp_get_max_threads();
  for (Damping damping : {Damping::study, Damping::implicit})
    for (int threads : {1, 3}) {
      World w = shaken_wall(damping, threads);
      State& s = w.state();
      for (int i = 0; i < 400; ++i) {
        s.velocity[0].x() += 6.0 * std::sin(2 * M_PI * 5.0 * s.time_s) * w.dt_s();
        w.step();
        if (i % 40 != 39) continue;
        ASSERT_TRUE(s.posed_ahead);
        State fresh = s;
        forget_step_motion(fresh);
        const bool moved = update_pose(w.model(), fresh);
        EXPECT_TRUE(same_bits(s.rotation, fresh.rotation)) << "step " << s.step << ", " << threads << " threads";
        EXPECT_TRUE(same_bits(s.face_normal_world, fresh.face_normal_world)) << "step " << s.step;
        EXPECT_TRUE(same_bits(s.face_offset_world, fresh.face_offset_world)) << "step " << s.step;
        EXPECT_EQ(s.moved_ahead, moved) << "step " << s.step;
      }
    }
  omp_set_num_threads(saved);
}

// A block moved after a step, with forget_step_motion (as a restore or a chaos probe's
// nudge), is posed where it now is: moved by twice the margin, it rebuilds the pair list.
TEST(Pose, ABlockMovedBetweenStepsIsPosedAnew) {
  const int saved = omp_get_max_threads();
  World w = shaken_wall(Damping::study, 2);
  State& s = w.state();
  for (int i = 0; i < 20; ++i) w.step();
  const long rebuilds = s.profile.broadphase_rebuilds;
  ASSERT_TRUE(s.posed_ahead);
  ASSERT_FALSE(s.moved_ahead);
  const int top = w.model().block_count - 1;
  s.position[top].z() += 2 * w.model().margin_m;
  forget_step_motion(s);
  w.step();
  EXPECT_EQ(s.profile.broadphase_rebuilds, rebuilds + 1);
  omp_set_num_threads(saved);
}

// Motion that no narrowphase has read yet adds up over the poses (a block moved and posed
// again before the pairs are searched), and the apart clock grows by a bound on any two
// blocks' relative shift: the shifts' spread summed over the axes (their 1-norm).
TEST(Pose, UnreadMotionAddsUpAndTheApartClockBoundsEveryRelativeShift) {
  const int saved = omp_get_max_threads();
  World w = shaken_wall(Damping::study, 1);
  State& s = w.state();
  for (int i = 0; i < 5; ++i) w.step();
  ASSERT_FALSE(s.step_motion_read);  // the step's integrate posed the blocks after its narrowphase
  const int top = w.model().block_count - 1;
  const Vec3 shift_before = s.step_shift[top], moved(1e-4, -2e-4, 0.0);
  s.position[top] += moved;
  update_pose(w.model(), s);
  EXPECT_LT((s.step_shift[top] - (shift_before + moved)).norm(), 1e-15);
  ASSERT_TRUE(s.apart_clock_valid);
  for (int b = 0; b < w.model().block_count; ++b)
    EXPECT_GE(s.apart_clock_step_m, (s.step_shift[top] - s.step_shift[b]).lpNorm<1>()) << "block " << b;
  const double turn_before = s.step_turn[top], angle = 1e-3;
  for (int turns = 0; turns < 2; ++turns) {
    s.orientation[top] = Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ())) * s.orientation[top];
    update_pose(w.model(), s);
  }
  EXPECT_GE(s.step_turn[top], turn_before + 2 * angle);
  EXPECT_LT(s.step_turn[top], turn_before + 2 * angle * (1 + 1e-6));
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace ishibashi
