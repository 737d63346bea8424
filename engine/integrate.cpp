// Semi-implicit (symplectic) Euler as in MODEL.md section 2: v += a dt, x += v dt.
// Rotation: Euler's equations in the principal frame, I dw/dt = M - w x (I w), then the
// orientation quaternion turns by w dt.
#include <cmath>
#include <sstream>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {

void integrate(const Model& m, State& s, double dt) {
  parallel_for(m.block_count, [&](std::ptrdiff_t b) {
    if (m.motion[b] == Motion::fixed) return;
    if (m.motion[b] == Motion::prescribed) {  // kinematic: velocities come from the driver
      s.position[b] += s.velocity[b] * dt;
      s.orientation[b] = (quat_from_rotation_vector(s.angular_velocity[b] * dt) * s.orientation[b]).normalized();
      return;
    }
    s.velocity[b] += (s.force[b] / m.mass_kg[b] + m.gravity_m_s2) * dt;
    s.position[b] += s.velocity[b] * dt;

    const Mat3& r = s.rotation[b];  // from the pose stage of this step
    const Vec3& inertia = m.inertia_kg_m2[b];
    Vec3 w = r.transpose() * s.angular_velocity[b];
    const Vec3 moment = r.transpose() * s.torque[b];
    w += (moment - w.cross(inertia.cwiseProduct(w))).cwiseQuotient(inertia) * dt;
    s.angular_velocity[b] = r * w;
    s.orientation[b] = (s.orientation[b] * quat_from_rotation_vector(w * dt)).normalized();
  });

  // A NaN spreads through every contact it touches: stop at once and say where.
  for (int b = 0; b < m.block_count; ++b)
    if (!s.position[b].allFinite() || !s.velocity[b].allFinite() || !s.angular_velocity[b].allFinite() ||
        !s.orientation[b].coeffs().allFinite()) {
      std::ostringstream msg;
      msg << "the state of " << m.block_label(b) << " is not finite (NaN or infinity) at t = " << s.time_s
          << " s, step " << s.step << "; the time step is probably too large for its contacts, or a load is invalid";
      throw ModelError(msg.str());
    }
}

}  // namespace ishibashi
