// Semi-implicit (symplectic) Euler as in MODEL.md section 2: v += a dt, x += v dt.
// Rotation: Euler's equations in the principal frame, I dw/dt = M - w x (I w), then the
// orientation quaternion turns by w dt. A free block whose centroid falls below the
// model (Model::leave_depth_m) is frozen there and its kinetic energy booked as lost.
#include <array>
#include <cmath>
#include <sstream>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {

BlockEnergy integrate(const Model& m, State& s, double dt) {
  std::array<BlockEnergy, kReductionChunks> parts{};
  std::array<int, kReductionChunks> first_not_finite;
  first_not_finite.fill(-1);
  const Vec3 down = m.gravity_m_s2.norm() > 0 ? Vec3(m.gravity_m_s2.normalized()) : Vec3::Zero();
  parallel_chunks(m.block_count, kReductionChunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    BlockEnergy e;
    for (std::ptrdiff_t b = begin; b < end; ++b) {
      if (m.motion[b] == Motion::fixed) continue;
      if (m.motion[b] == Motion::prescribed) {  // kinematic: velocities come from the driver
        s.position[b] += s.velocity[b] * dt;
        s.orientation[b] = (quat_from_rotation_vector(s.angular_velocity[b] * dt) * s.orientation[b]).normalized();
      } else if (s.left_model[b]) {  // frozen where it left the model: only its weight counts
        e.gravitational_j -= m.mass_kg[b] * m.gravity_m_s2.dot(s.position[b]);
      } else {
        const Mat3& r = s.rotation[b];  // from the pose stage of this step
        const Vec3& inertia = m.inertia_kg_m2[b];
        Vec3 w = r.transpose() * s.angular_velocity[b];
        e.kinetic_j += 0.5 * m.mass_kg[b] * s.velocity[b].squaredNorm() + 0.5 * w.dot(inertia.cwiseProduct(w));
        e.gravitational_j -= m.mass_kg[b] * m.gravity_m_s2.dot(s.position[b]);

        s.velocity[b] += (s.force[b] / m.mass_kg[b] + m.gravity_m_s2) * dt;
        s.position[b] += s.velocity[b] * dt;
        const Vec3 moment = r.transpose() * s.torque[b];
        w += (moment - w.cross(inertia.cwiseProduct(w))).cwiseQuotient(inertia) * dt;
        s.angular_velocity[b] = r * w;
        s.orientation[b] = (s.orientation[b] * quat_from_rotation_vector(w * dt)).normalized();
        if (down.dot(s.position[b]) > m.leave_depth_m) {
          s.left_model[b] = 1;
          // Its kinetic energy, plus the half step of fall that the pose-averaged
          // gravitational energy (World::step) has yet to count.
          e.left_model_j += 0.5 * m.mass_kg[b] * s.velocity[b].squaredNorm() + 0.5 * w.dot(inertia.cwiseProduct(w)) +
                            0.5 * m.mass_kg[b] * dt * m.gravity_m_s2.dot(s.velocity[b]);
          s.velocity[b] = s.angular_velocity[b] = Vec3::Zero();
        }
      }
      const bool finite = s.position[b].allFinite() && s.velocity[b].allFinite() &&
                          s.angular_velocity[b].allFinite() && s.orientation[b].coeffs().allFinite();
      if (!finite && first_not_finite[k] < 0) first_not_finite[k] = static_cast<int>(b);
    }
    parts[k] = e;
  });

  // A NaN spreads through every contact it touches: stop at once and say where.
  for (int b : first_not_finite)
    if (b >= 0) {
      std::ostringstream msg;
      msg << "the state of " << m.block_label(b) << " is not finite (NaN or infinity) at t = " << s.time_s
          << " s, step " << s.step << "; the time step is probably too large for its contacts, or a load is invalid";
      throw ModelError(msg.str());
    }
  BlockEnergy total;
  for (const BlockEnergy& e : parts) {
    total.kinetic_j += e.kinetic_j;
    total.gravitational_j += e.gravitational_j;
    total.left_model_j += e.left_model_j;
  }
  return total;
}

}  // namespace ishibashi
