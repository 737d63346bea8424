// The thread tuner against synthetic step times: it leaves a team that a smaller one
// beats, comes back when the larger one is fast again, and never moves without adaptive.
#include <gtest/gtest.h>

#include <functional>

#include "engine/thread_tuner.h"

namespace ishibashi {
namespace {

// Feeds `steps` steps whose wall time depends on the team size; returns the final team.
int run(ThreadTuner& tuner, long steps, const std::function<double(int)>& step_s) {
  for (long i = 0; i < steps; ++i) tuner.record(step_s(tuner.threads()));
  return tuner.threads();
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

TEST(ThreadTuner, FixedWhenNotAdaptive) {
  ThreadTuner t(8, false);
  EXPECT_EQ(run(t, 20000, [](int n) { return 1e-4 * n; }), 8);
}

}  // namespace
}  // namespace ishibashi
