// Chooses the team size of a run's steps from their measured wall time. The most threads
// are not always the fastest: a small model's loops are shorter than posting them to the
// team and waiting for its last chunks, and when another process holds some of the cores
// a thread descheduled in the middle of a chunk holds up its loop (team.h). Results never
// depend on the team size (fixed chunking, parallel.h), so it may change at any step; only
// the speed does.
//
// The tuner measures windows of steps (at least kWindowS of wall time) on the team size
// it holds best, and every kProbeEvery windows one window on a neighbouring size of the
// ladder 1, 2, 4, ..., max (alternately smaller and larger), moving there when that was
// faster by more than the noise.
#pragma once
#include <vector>

namespace ishibashi {

class ThreadTuner {
 public:
  // max_threads: the largest team (the run's --threads); adaptive = false always uses it.
  explicit ThreadTuner(int max_threads, bool adaptive = true);

  int threads() const { return ladder_[current_]; }
  int max_threads() const { return ladder_.back(); }
  void set_adaptive(bool adaptive);
  // After every step: its wall time.
  void record(double step_s);

  static constexpr double kWindowS = 0.02;  // long enough to average over scheduler ticks
  static constexpr int kProbeEvery = 8;     // windows at the best size between probes
  static constexpr double kMargin = 0.9;    // a probe must save 10 % to move

 private:
  std::vector<int> ladder_;    // 1, 2, 4, ..., max_threads
  std::vector<double> cost_;   // seconds per step on each rung (0: not measured yet)
  int current_ = 0, best_ = 0;
  bool adaptive_ = true, probe_down_ = true;
  double window_s_ = 0;
  long window_steps_ = 0;
  long windows_ = 0;
};

}  // namespace ishibashi
