// The thread tuner against synthetic step times: it leaves a team that a smaller one
// beats, comes back when the larger one is fast again, and never moves without adaptive.
#include <gtest/gtest.h>

#include <functional>

#include "engine/thread_tuner.h"

namespace ishibashi {
namespace {

// Feeds `steps` steps whose wall time depends on the team size; returns the team the tuner
// holds best at the end (the one it runs on outside its probes).
int run(ThreadTuner& tuner, long steps, const std::function<double(int)>& step_s) {
  for (long i = 0; i < steps; ++i) tuner.record(step_s(tuner.threads()));
  return tuner.best_threads();
}

TEST(ThreadTuner, LadderStartsWithEveryThread) {
  EXPECT_EQ(ThreadTuner(1).threads(), 1);
  EXPECT_EQ(ThreadTuner(6).threads(), 6);
  ThreadTuner t(6);
  // Linear scaling: the most threads stay best.
  EXPECT_EQ(run(t, 100000, [](int n) { return 1e-3 / n; }), 6);
}

TEST(ThreadTuner, MovesToTheFastestTeamAndBackWhenTheLoadChanges) {
  ThreadTuner t(16);
  // A small model: barriers cost more than the work, one thread is fastest.
  EXPECT_EQ(run(t, 20000, [](int n) { return 1e-4 + 2e-5 * (n - 1); }), 1);
  // A large model on a machine where 4 cores are free: 4 threads are fastest.
  EXPECT_EQ(run(t, 20000, [](int n) { return n <= 4 ? 4e-3 / n : 4e-3; }), 4);
  // The other process ends: 16 threads scale again.
  EXPECT_EQ(run(t, 20000, [](int n) { return 1.6e-2 / n; }), 16);
}

// On a quiet machine where two threads are twice as fast, the probes on one thread grow
// rarer as they keep losing (every eighth window they would be 6.7 % of the steps), and
// when another process takes a core the tuner still leaves two threads within a few
// windows (each at least ThreadTuner::kWindowS of wall time).
TEST(ThreadTuner, ProbesLessOftenWhileTheyLoseAndStillFollowTheLoad) {
  ThreadTuner t(2);
  ASSERT_EQ(run(t, 200000, [](int n) { return 2e-3 / n; }), 2);  // 200 s: backed off
  long on_one = 0;
  for (long i = 0; i < 200000; ++i) {
    on_one += t.threads() == 1;
    t.record(2e-3 / t.threads());
  }
  EXPECT_LT(on_one, 0.015 * 200000);
  EXPECT_GT(on_one, 0);  // it still probes
  // Another process now holds a core: two threads are three times slower than one.
  const auto busy = [](int n) { return n == 2 ? 6e-3 : 2e-3; };
  EXPECT_EQ(run(t, 60, busy), 1);  // 60 steps: 15 windows at most
  // And back, once the core is free again.
  EXPECT_EQ(run(t, 20000, [](int n) { return 2e-3 / n; }), 2);
}

TEST(ThreadTuner, FixedWhenNotAdaptive) {
  ThreadTuner t(8, false);
  EXPECT_EQ(run(t, 20000, [](int n) { return 1e-4 * n; }), 8);
}

}  // namespace
}  // namespace ishibashi
