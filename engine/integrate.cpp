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
    const Mat3 r = s.orientation[b].toRotationMatrix();
    const Vec3& inertia = m.inertia_kg_m2[b];
    const Mat6& damping = s.block_damping[b];
    Vec3 w;  // new angular velocity, principal frame
    if (damping.isZero(0.0)) {
      s.velocity[b] += (s.force[b] / m.mass_kg[b] + m.gravity_m_s2) * dt;
      w = r.transpose() * s.angular_velocity[b];
      const Vec3 moment = r.transpose() * s.torque[b];
      w += (moment - w.cross(inertia.cwiseProduct(w))).cwiseQuotient(inertia) * dt;
      s.block_damping_work_j[b] = 0.0;
    } else {
      // The block's own dashpots act at the new velocity, (M + dt D) du = dt F, so that
      // the study's critical dashpots (h = 1) do not limit the step; the dashpots of its
      // neighbours' motion stay explicit. -D du is the force this adds; its work at the
      // step's mean velocity is booked as dissipation.
      const Mat3 inertia_world = r * inertia.asDiagonal() * r.transpose();
      const Vec3 w_world = s.angular_velocity[b];
      Vec6 load, u;
      load << s.force[b] + m.mass_kg[b] * m.gravity_m_s2, s.torque[b] - w_world.cross(inertia_world * w_world);
      u << s.velocity[b], w_world;
      Mat6 system = dt * damping;
      system.topLeftCorner<3, 3>().diagonal().array() += m.mass_kg[b];
      system.bottomRightCorner<3, 3>() += inertia_world;
      const Vec6 du = system.ldlt().solve(dt * load);
      s.block_damping_work_j[b] = (damping * du).dot(u + 0.5 * du) * dt;
      s.velocity[b] += du.head<3>();
      w = r.transpose() * (w_world + du.tail<3>());
    }
    s.position[b] += s.velocity[b] * dt;
    s.angular_velocity[b] = r * w;
    s.orientation[b] = (s.orientation[b] * quat_from_rotation_vector(w * dt)).normalized();
  });
  double damping_work = 0.0;  // in block order: the same sum for any thread count
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free) damping_work += s.block_damping_work_j[b];
  s.energy.damping_j += damping_work;

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
