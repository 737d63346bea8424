#include "engine/state.h"

#include <algorithm>
#include <limits>

namespace ishibashi {

void SubContacts::copy_range(const SubContacts& src, std::size_t from, std::size_t count, std::size_t to) {
#define ISHIBASHI_COPY_FIELD(type, name, comment) std::copy_n(src.name.begin() + from, count, name.begin() + to);
  ISHIBASHI_SUB_CONTACT_FIELDS(ISHIBASHI_COPY_FIELD)
#undef ISHIBASHI_COPY_FIELD
}

bool is_fallen(const Model& m, const State& s, int b) {
  return m.motion[b] == Motion::free && m.initial_position[b].z() - s.position[b].z() > m.size_m[b];
}

State make_initial_state(const Model& model) {
  State s;
  const int nb = model.block_count;
  s.position = model.initial_position;
  s.orientation = model.initial_orientation;
  s.velocity.assign(nb, Vec3::Zero());
  s.angular_velocity.assign(nb, Vec3::Zero());
  s.driven_velocity.assign(nb, Vec3::Zero());
  s.driven_angular_velocity.assign(nb, Vec3::Zero());
  s.applied_force.assign(nb, Vec3::Zero());
  s.applied_torque.assign(nb, Vec3::Zero());
  s.force.assign(nb, Vec3::Zero());
  s.torque.assign(nb, Vec3::Zero());
  s.left_model.assign(nb, 0);
  s.damping_scale.assign(nb, 1.0);
  s.prescribed_force_carried.assign(nb, Vec3::Zero());
  s.prescribed_moment_carried.assign(nb, Vec3::Zero());
  for (int b = 0; b < nb; ++b)  // a block's motion never changes: listed once
    if (model.motion[b] == Motion::prescribed) s.prescribed_block.push_back(b);
  const std::size_t nt = model.ties.size();
  s.tie_plastic_m.assign(nt, 0.0);
  s.tie_tension_n.assign(nt, 0.0);
  s.tie_peak_tension_n.assign(nt, 0.0);
  s.tie_force_n.assign(nt, Vec3::Zero());
  s.tie_moment_nm.assign(2 * nt, Vec3::Zero());
  s.rotation.resize(nb);
  s.face_normal_world.resize(model.face_normal_local.size());
  s.face_offset_world.resize(model.face_offset_local.size());
  s.position_at_rebuild = s.position;
  forget_step_motion(s);
  return s;
}

void forget_step_motion(State& s) {
  s.position_at_pose = s.position;
  s.orientation_at_pose = s.orientation;
  s.step_shift.assign(s.position.size(), Vec3::Zero());
  s.step_turn.assign(s.position.size(), std::numeric_limits<double>::infinity());
  s.step_motion_read = false;
  s.posed_ahead = false;
}

}  // namespace ishibashi
