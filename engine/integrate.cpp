// Semi-implicit (symplectic) Euler as in MODEL.md section 2: v += a dt, x += v dt.
// Rotation: Euler's equations in the principal frame, I dw/dt = M - w x (I w), then the
// orientation quaternion turns by w dt. A free block whose centroid falls below the
// model (Model::leave_depth_m) is frozen there and its kinetic energy booked as lost.
// With explicit dashpots each block's forces are gathered just before it moves, in the
// same pass: as loops of their own gather and integrate each cost a team post and a tail
// (model F on 16 threads: 24 and 23 us a step for 9 and 11 us of work a thread); with
// implicit ones the solve's impulse is added there (and the gather is the solve's first
// pass), where the booking of that impulse was a loop of its own. For the
// same reason each chunk's blocks are posed for the next step once they have moved
// (pose.cpp): the pose's own loop took 22 us a step on 16 threads for 5 us of work a thread
// (perf/results, session 72).
#include <array>
#include <cmath>
#include <sstream>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

// Block b's step over dt from State::force and torque; adds its energy before the step to
// e. Returns false when its state is no longer finite.
bool integrate_block(const Model& m, State& s, double dt, const Vec3& down, std::ptrdiff_t b, BlockEnergy& e) {
  if (m.motion[b] == Motion::fixed) return true;
  if (m.motion[b] == Motion::prescribed) {  // kinematic: velocities come from the driver
    // (State::velocity keeps those of the move before until the step ends: the other chunks'
    // ground work reads them.)
    s.position[b] += s.driven_velocity[b] * dt;
    s.orientation[b] = (quat_from_rotation_vector(s.driven_angular_velocity[b] * dt) * s.orientation[b]).normalized();
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
  return s.position[b].allFinite() && s.velocity[b].allFinite() && s.angular_velocity[b].allFinite() &&
         s.orientation[b].coeffs().allFinite();
}

// What a pass adds to each block's forces just before it moves.
enum class Forces { gathered, dashpot_impulse };

// The pass over the blocks in the stage chunks (those of the gather and the pair loops),
// adding `forces` to each block's before it moves, and posing the chunk's blocks once they
// have moved; the chunks' sums added in chunk order. A block's forces, step and pose read and
// write its own entries alone (its pairs' forces, which the contact law wrote, aside).
ForcesAndMotion integrate_blocks(const Model& m, State& s, double dt, Forces forces) {
  const bool gather = forces == Forces::gathered;
  std::array<BlockEnergy, kStageChunks> parts{};
  std::array<double, kStageChunks> power{};         // Forces::gathered: the prescribed blocks'
  std::array<double, kStageChunks> dashpot_work{};  // Forces::dashpot_impulse
  std::array<PoseChunk, kStageChunks> poses;
  std::array<int, kStageChunks> first_not_finite;
  first_not_finite.fill(-1);
  const Vec3 down = m.gravity_m_s2.norm() > 0 ? Vec3(m.gravity_m_s2.normalized()) : Vec3::Zero();
  const bool add = begin_pose(s);
  const int chunks = stage_chunks(m.block_count);
  parallel_chunks(m.block_count, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    // Before this chunk's blocks move: the power reads the prescribed blocks' velocities
    // (which no pass changes) and the pair forces.
    if (gather) power[k] = prescribed_power_of_chunk(s, k);
    BlockEnergy e;
    PoseChunk pose;
    for (std::ptrdiff_t b = begin; b < end; ++b) {
      if (gather)
        gather_block(m, s, b);
      else
        dashpot_work[k] += apply_dashpot_impulse(m, s, dt, b);
      if (!integrate_block(m, s, dt, down, b, e) && first_not_finite[k] < 0) first_not_finite[k] = static_cast<int>(b);
    }
    // A loop of its own over the chunk's blocks, still in the cache: interleaved with the
    // step above, the pose made the pass slower than the two passes apart (one thread).
    for (std::ptrdiff_t b = begin; b < end; ++b) pose_block(m, s, b, add, pose);
    parts[k] = e;
    poses[k] = pose;
  });

  // A NaN spreads through every contact it touches: stop at once and say where.
  for (int b : first_not_finite)
    if (b >= 0) {
      std::ostringstream msg;
      msg << "the state of " << m.block_label(b) << " is not finite (NaN or infinity) at t = " << s.time_s
          << " s, step " << s.step << "; the time step is probably too large for its contacts, or a load is invalid";
      throw ModelError(msg.str());
    }
  s.moved_ahead = finish_pose(m, s, poses.data(), chunks);
  s.posed_ahead = true;
  ForcesAndMotion total;
  if (gather) total.prescribed_power_w = carried_prescribed_power(s);
  for (int k = 0; k < chunks; ++k) {
    total.energy.kinetic_j += parts[k].kinetic_j;
    total.energy.gravitational_j += parts[k].gravitational_j;
    total.energy.left_model_j += parts[k].left_model_j;
    total.prescribed_power_w += power[k];
    total.dashpot_work_j += dashpot_work[k];
  }
  return total;
}

}  // namespace

ForcesAndMotion gather_and_integrate(const Model& m, State& s, double dt) {
  return integrate_blocks(m, s, dt, Forces::gathered);
}

ForcesAndMotion integrate_with_dashpots(const Model& m, State& s, double dt) {
  return integrate_blocks(m, s, dt, Forces::dashpot_impulse);
}

}  // namespace ishibashi
