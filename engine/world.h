// A running simulation: the Model, its State and the time step. step() reads as the
// table of contents of the method: pose, broadphase, narrowphase, contact law, gather,
// integrate, each timed into State::profile.
#pragma once
#include <cstdint>

#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

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
  // its contacts (Cundall's 2 sqrt(m / K_n) for an undamped bounce). Sets *block to the
  // limiting block.
  double critical_time_step_s(int* block = nullptr) const;

  // Hash of positions, orientations and velocities (for determinism checks).
  std::uint64_t state_hash() const;

 private:
  Model model_;
  State state_;
  double dt_s_;
};

}  // namespace ishibashi
