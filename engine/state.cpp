#include "engine/state.h"

#include <algorithm>

namespace ishibashi {

void SubContacts::clear() { resize(0); }

void SubContacts::resize(std::size_t n) {
  block_a.resize(n);
  block_b.resize(n);
  key.resize(n);
  point.resize(n);
  normal.resize(n);
  gap_m.resize(n);
  gap_change_m.resize(n);
  area_m2.resize(n);
  normal_stiffness_n_m.resize(n);
  shear_stiffness_n_m.resize(n);
  normal_damping_n_s_m.resize(n);
  shear_damping_n_s_m.resize(n);
  normal_stretch_m.resize(n);
  shear_stretch_m.resize(n);
  damping_force_n.resize(n);
  slip_m.resize(n);
  incident_local.resize(n);
  flags.resize(n);
}

void SubContacts::copy_range(const SubContacts& s, std::size_t from, std::size_t count, std::size_t to) {
  auto copy = [&](const auto& src, auto& dst) { std::copy_n(src.begin() + from, count, dst.begin() + to); };
  copy(s.block_a, block_a);
  copy(s.block_b, block_b);
  copy(s.key, key);
  copy(s.point, point);
  copy(s.normal, normal);
  copy(s.gap_m, gap_m);
  copy(s.gap_change_m, gap_change_m);
  copy(s.area_m2, area_m2);
  copy(s.normal_stiffness_n_m, normal_stiffness_n_m);
  copy(s.shear_stiffness_n_m, shear_stiffness_n_m);
  copy(s.normal_damping_n_s_m, normal_damping_n_s_m);
  copy(s.shear_damping_n_s_m, shear_damping_n_s_m);
  copy(s.normal_stretch_m, normal_stretch_m);
  copy(s.shear_stretch_m, shear_stretch_m);
  copy(s.damping_force_n, damping_force_n);
  copy(s.slip_m, slip_m);
  copy(s.incident_local, incident_local);
  copy(s.flags, flags);
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
  s.applied_force.assign(nb, Vec3::Zero());
  s.applied_torque.assign(nb, Vec3::Zero());
  s.force.assign(nb, Vec3::Zero());
  s.torque.assign(nb, Vec3::Zero());
  s.left_model.assign(nb, 0);
  s.damping_scale.assign(nb, 1.0);
  s.rotation.resize(nb);
  s.face_normal_world.resize(model.face_normal_local.size());
  s.face_offset_world.resize(model.face_offset_local.size());
  s.position_at_rebuild = s.position;
  return s;
}

}  // namespace ishibashi
