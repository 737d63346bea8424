// Results do not depend on the number of threads: bit-identical states.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "engine/world.h"
#include "geometry/demo_scenes.h"

namespace ishibashi {
namespace {

// The wall's base (block 0) shaken sideways at 0.8 g, 5 Hz, for `steps` steps.
void shake(World& w, int steps) {
  State& s = w.state();
  for (int i = 0; i < steps; ++i) {
    s.velocity[0].x() += 0.8 * 9.81 * std::sin(2 * M_PI * 5.0 * s.time_s) * w.dt_s();
    w.step();
  }
}

// adaptive = false: every step on `threads`; true: on the team sizes the tuner picks.
// Damping::capped: dashpots capped at three times the step, which the caps, recomputed at
// every pair-list rebuild, keep stable; Damping::implicit: the same step, the dashpots
// solved for by conjugate gradients (their sums in fixed chunks).
std::uint64_t shaken_wall_hash(int threads, bool adaptive = false, long* thread_steps = nullptr,
                               Damping damping = Damping::study) {
  omp_set_num_threads(threads);
  WallSpec spec;
  spec.courses = 5;
  spec.stones_per_course = 14;  // 141 blocks: enough for the loops to run on threads
  spec.leaves = 2;
  spec.options.damping = damping;
  World w(make_wall_model(spec), damping == Damping::study ? 1e-5 : 3e-5);
  if (damping == Damping::capped) {
    EXPECT_LT(*std::min_element(w.state().damping_scale.begin(), w.state().damping_scale.end()), 1.0);
  }
  w.set_adaptive_threads(adaptive);
  shake(w, 3000);
  const State& s = w.state();
  EXPECT_GT(sub_contact_count(s), 100);
  if (thread_steps) *thread_steps = s.profile.thread_steps;
  return w.state_hash();
}

TEST(Determinism, SameStateHashForOneToFourThreads) {
  const int saved = omp_get_max_threads();
  const std::uint64_t one = shaken_wall_hash(1);
  for (int threads : {2, 3, 4}) EXPECT_EQ(shaken_wall_hash(threads), one) << threads << " threads";
  omp_set_num_threads(saved);
}

TEST(Determinism, CappedAndImplicitDashpotsSameStateHashForOneToFourThreads) {
  const int saved = omp_get_max_threads();
  for (Damping damping : {Damping::capped, Damping::implicit}) {
    const std::uint64_t one = shaken_wall_hash(1, false, nullptr, damping);
    for (int threads : {2, 3, 4})
      EXPECT_EQ(shaken_wall_hash(threads, false, nullptr, damping), one) << threads << " threads, " << damping_name(damping);
  }
  omp_set_num_threads(saved);
}

// The tuner changes the team size during the run (it probes 1, 2 and 4 threads): the
// state stays bit-identical to one thread's. Whether it moves within 3,000 steps depends
// on the timing (about one run in twelve kept 4 threads throughout on a quiet 2-core
// machine; the test failed twice beside three or four busy processes in session 82, most
// likely so: 250 repeats under load gave the one-thread hash), so the run is repeated, up to
// ten times, until its team changed; every run must match.
TEST(Determinism, SameStateHashWhenTheTeamSizeChangesDuringTheRun) {
  const int saved = omp_get_max_threads();
  const std::uint64_t one = shaken_wall_hash(1);
  long thread_steps = 4 * 3000L;
  for (int run = 0; run < 10 && thread_steps == 4 * 3000L; ++run)
    EXPECT_EQ(shaken_wall_hash(4, true, &thread_steps), one) << "run " << run;
  EXPECT_NE(thread_steps, 4 * 3000L) << "the team size never changed in ten runs";
  omp_set_num_threads(saved);
}

// The motion hash is the blocks' part of the state hash: one ulp of a sub-contact's shear
// stretch moves the state hash alone, one ulp of a block's spin moves both. A narrowphase
// change that keeps or drops open points (which carry nothing) keeps the motion hash.
TEST(Determinism, MotionHashCoversTheBlocksAndNotTheSubContacts) {
  WallSpec spec;
  spec.courses = 3;
  spec.stones_per_course = 6;
  World w(make_wall_model(spec), 1e-5);
  shake(w, 300);
  State& s = w.state();
  const std::uint64_t state = w.state_hash(), motion = w.motion_hash();
  EXPECT_NE(state, motion);
  const auto touched = std::find_if(s.pairs.begin(), s.pairs.end(), [](const Pair& p) { return p.sub_count > 0; });
  ASSERT_NE(touched, s.pairs.end());
  double& stretch = s.contacts.shear_stretch_m[touched->sub_begin].x();
  const double kept = stretch;
  stretch = std::nextafter(stretch, 1.0);
  EXPECT_NE(w.state_hash(), state);
  EXPECT_EQ(w.motion_hash(), motion);
  stretch = kept;
  double& spin = s.angular_velocity.back().z();
  spin = std::nextafter(spin, 1.0);
  EXPECT_NE(w.state_hash(), state);
  EXPECT_NE(w.motion_hash(), motion);
}

}  // namespace
}  // namespace ishibashi
