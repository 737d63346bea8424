// Natural frequencies by impulse response (MODEL.md section 6.1): the ground (the fixed
// blocks) makes a short step in one direction, the joints originally in contact are held
// linear (they carry tension, never fail; no gravity needed, no damping), and the response
// of a monitored block is recorded along a chosen axis (the excitation's or another: an x
// step read in z shows how the structure couples the two).
#pragma once
#include <array>
#include <vector>

#include "engine/model.h"

namespace ishibashi {

struct ImpulseResponse {
  double dt_s;
  // The monitored block's displacement relative to the ground along x, y and z, one value
  // per step (the excitation's axis, and the others: an x step read in z shows how the
  // structure couples the two).
  std::array<std::vector<double>, 3> displacement_m;
};

// Ground step of `step_m` along excitation_axis (0 x, 1 y, 2 z) over `rise_s`, then
// `duration_s` of free vibration. dt_s = 0: a tenth of the stability limit (frequencies
// within 0.2 % up to the stiffest mode).
// linear_model: built with ModelOptions::linear_joints.
ImpulseResponse impulse_response(const Model& linear_model, int excitation_axis, int monitor_block, double duration_s,
                                 double dt_s = 0.0, double step_m = 1e-4, double rise_s = 2e-3);

}  // namespace ishibashi
