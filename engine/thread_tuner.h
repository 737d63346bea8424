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
// faster by more than the noise. A probe costs: on a quiet 2-core machine every eighth
// window ran on one thread, 5-6 % of a run's speed. So each probe that is clearly slower
// doubles the windows until the next (up to kProbeEveryMost), and a move, or the best
// size's cost changing by kLoadChange since the last probe (another process started or
// ended), brings the interval back to kProbeEvery. (Probing at once on such a change
// probed far more often beside a busy process, whose noise the change test then read as
// changes: model F 1.4 times slower there.)
#pragma once
#include <vector>

namespace ishibashi {

class ThreadTuner {
 public:
  // max_threads: the largest team (the run's --threads); adaptive = false always uses it.
  explicit ThreadTuner(int max_threads, bool adaptive = true);

  int threads() const { return ladder_[current_]; }  // for the next step (a probe's size during one)
  int best_threads() const { return ladder_[best_]; }
  int max_threads() const { return ladder_.back(); }
  void set_adaptive(bool adaptive);
  // After every step: its wall time.
  void record(double step_s);

  static constexpr double kWindowS = 0.02;  // long enough to average over scheduler ticks
  static constexpr int kProbeEvery = 8;     // windows at the best size between probes, at first
  static constexpr int kProbeEveryMost = 64;  // ... after probes that kept losing
  static constexpr double kMargin = 0.9;    // a probe must save 10 % to move
  static constexpr double kLoadChange = 0.3;  // the best size's cost moving this much: back to kProbeEvery

 private:
  std::vector<int> ladder_;    // 1, 2, 4, ..., max_threads
  std::vector<double> cost_;   // seconds per step on each rung (0: not measured yet)
  int current_ = 0, best_ = 0;
  bool adaptive_ = true, probe_down_ = true;
  double window_s_ = 0;
  long window_steps_ = 0;
  int probe_every_ = kProbeEvery, windows_to_probe_ = kProbeEvery;
  double cost_after_probe_ = 0;  // the best size's cost in the first window after the last probe
};

}  // namespace ishibashi
