#include "analysis/dynamics/impulse.h"

#include <cmath>

#include "engine/world.h"

namespace ishibashi {

ImpulseResponse impulse_response(const Model& model, int axis, int monitor, double duration_s, double dt_s, double step_m,
                                 double rise_s) {
  // Explicit integration shifts a frequency by about (omega dt)^2 / 24: a tenth of the
  // stability limit (omega dt <= 0.2) keeps that below 0.2 % for the stiffest mode.
  const double dt = dt_s > 0 ? dt_s : 0.1 * World(model, 1e-9).critical_time_step_s();
  World w(model, dt);
  State& s = w.state();
  const Model& m = w.model();
  ImpulseResponse r;
  r.dt_s = dt;
  const long steps = std::lround(duration_s / dt);
  // A smooth ground step (half-sine velocity pulse): it excites the low modes without
  // leaving the ground moving.
  double ground = 0;  // along the excitation axis
  for (long k = 0; k < steps; ++k) {
    const double t = (k + 0.5) * dt;
    const double v = t < rise_s ? step_m * M_PI / (2 * rise_s) * std::sin(M_PI * t / rise_s) : 0.0;
    for (int b = 0; b < m.block_count; ++b)
      if (m.motion[b] == Motion::prescribed) {
        s.velocity[b] = Vec3::Zero();
        s.velocity[b][axis] = v;
      }
    w.step();
    ground += v * dt;
    for (int c = 0; c < 3; ++c)
      r.displacement_m[c].push_back(s.position[monitor][c] - m.initial_position[monitor][c] - (c == axis ? ground : 0.0));
  }
  return r;
}

}  // namespace ishibashi
