// A running simulation: the Model, its State and the time step. step() reads as the
// table of contents of the method: pose, broadphase, narrowphase, contact law, gather,
// integrate, each timed into State::profile.
#pragma once
#include <cstdint>

#include "engine/model.h"
#include "engine/state.h"
#include "engine/thread_tuner.h"

namespace ishibashi {

class Team;

class World {
 public:
  // Detects the joints originally in contact (these may carry a bond), then checks the
  // model: throws ModelError when blocks overlap or dt exceeds the stability limit.
  World(Model model, double dt_s);

  void step();
  void run(long steps) {
    for (long i = 0; i < steps; ++i) step();
  }

  const Model& model() const { return model_; }
  State& state() { return state_; }
  const State& state() const { return state_; }
  double dt_s() const { return dt_s_; }

  // Largest stable dt over the free blocks: for each block and degree of freedom,
  // 2/omega (sqrt(1 + zeta^2) - zeta) with omega^2 = K/M and zeta the damping ratio of
  // its contacts (Cundall's 2 sqrt(m / K_n) for an undamped bounce; zeta = 0 when the
  // dashpots are capped, as the caps keep them within it). Sets *block to the limiting block.
  double critical_time_step_s(int* block = nullptr) const;

  // Bonds every sub-contact originally in contact whose materials carry one and that has
  // none (ModelOptions::bonds_when_settled), in its current pose; returns how many.
  int form_bonds();

  // Hash of every block's position, orientation, velocity and spin, then of each pair's
  // sub-contacts' shear stretches, open points' zeros included (determinism checks).
  std::uint64_t state_hash() const;
  // The blocks' part alone: a change that moves state_hash but not motion_hash changed
  // which sub-contacts a run keeps (open points that carry nothing), not how it moves.
  std::uint64_t motion_hash() const;

  // The steps run on at most the threads OpenMP gave the constructing thread, on the team
  // size found fastest as they go (thread_tuner.h); set_adaptive_threads(false) always
  // uses them all (scaling benchmarks). The results are the same either way.
  void set_adaptive_threads(bool adaptive) { tuner_.set_adaptive(adaptive); }
  const ThreadTuner& thread_tuner() const { return tuner_; }

  // Times each thread's share of every stage into State::profile (work, waiting,
  // imbalance); off by default (two clock reads per thread and loop). A state restored
  // from a checkpoint whose steps were timed goes on timed, so that its profile's team
  // times cover every step (Profile::threads_timed).
  void set_thread_timing(bool on);
  // Keeps a timeline of steps [first_step, last_step): one slice per thread and stage, and
  // the step on the calling thread's track (turns the thread timing on).
  void trace_steps(long first_step, long last_step);
  const StageTrace& trace() const { return trace_; }

 private:
  const Model model_;  // built once with its options (ModelBuilder::build), never edited
  State state_;
  double dt_s_;
  ThreadTuner tuner_;
  StageTrace trace_;
  bool time_threads_ = false;  // set_thread_timing's, which a restored state does not overwrite

  template <class Fn>
  auto timed(Stage stage, Fn&& fn);
  void note_stage(const Team& team, Stage stage, int threads, double begin_s);
};

}  // namespace ishibashi
