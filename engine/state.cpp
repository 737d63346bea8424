#include "engine/state.h"

namespace ishibashi {

void SubContacts::clear() { resize(0); }

void SubContacts::resize(std::size_t n) {
  pair.resize(n);
  block_a.resize(n);
  block_b.resize(n);
  key.resize(n);
  point.resize(n);
  normal.resize(n);
  gap_m.resize(n);
  gap_change_m.resize(n);
  area_m2.resize(n);
  lever_a_m.resize(n);
  lever_b_m.resize(n);
  normal_spring_n.resize(n);
  shear_spring_n.resize(n);
  force_n.resize(n);
  damping_force_n.resize(n);
  slip_m.resize(n);
  incident_local.resize(n);
  flags.resize(n);
}

void SubContacts::copy_from(const SubContacts& s, std::size_t at) {
  auto copy = [&](const auto& from, auto& to) { std::copy(from.begin(), from.end(), to.begin() + at); };
  copy(s.pair, pair);
  copy(s.block_a, block_a);
  copy(s.block_b, block_b);
  copy(s.key, key);
  copy(s.point, point);
  copy(s.normal, normal);
  copy(s.gap_m, gap_m);
  copy(s.gap_change_m, gap_change_m);
  copy(s.area_m2, area_m2);
  copy(s.lever_a_m, lever_a_m);
  copy(s.lever_b_m, lever_b_m);
  copy(s.normal_spring_n, normal_spring_n);
  copy(s.shear_spring_n, shear_spring_n);
  copy(s.force_n, force_n);
  copy(s.damping_force_n, damping_force_n);
  copy(s.slip_m, slip_m);
  copy(s.incident_local, incident_local);
  copy(s.flags, flags);
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
  s.travel_m.assign(nb, 0.0);
  s.turn_rad.assign(nb, 0.0);
  s.torque.assign(nb, Vec3::Zero());
  s.vertex_world.resize(model.vertex_local.size());
  s.face_normal_world.resize(model.face_normal_local.size());
  s.face_offset_world.resize(model.face_offset_local.size());
  s.direction_world.resize(model.direction_local.size());
  s.block_contact_begin.assign(nb + 1, 0);
  s.position_at_rebuild = s.position;
  return s;
}

}  // namespace ishibashi
