#include "engine/checkpoint.h"

#include <algorithm>

namespace ishibashi {
namespace {

template <class Fn>
void for_each_array(Joints& j, Fn&& fn) {
  fn(j.block_a), fn(j.block_b), fn(j.point_begin), fn(j.point_on_a), fn(j.point_on_b), fn(j.centre_on_a);
  fn(j.centre_on_b), fn(j.normal_on_a), fn(j.reference_on_a), fn(j.centre_reference_on_a), fn(j.opening_m);
  fn(j.slip_m), fn(j.broken_at_reference), fn(j.bond_broken), fn(j.cracked);
}

}  // namespace

CheckpointReader::CheckpointReader(std::istream& in) : in_(in) {
  const std::streampos here = in_.tellg();
  in_.seekg(0, std::ios::end);
  end_ = in_.tellg();
  in_.seekg(here);
}

std::size_t CheckpointReader::size(std::size_t element_bytes) {
  const auto n = value<std::uint64_t>();
  const auto left = static_cast<std::uint64_t>(std::max<std::streamoff>(0, end_ - in_.tellg()));
  if (n > left / element_bytes)
    throw CheckpointError("an array of " + std::to_string(n) + " elements where " + std::to_string(left) + " bytes are left");
  return static_cast<std::size_t>(n);
}

bool CheckpointReader::flag() {
  const auto byte = value<std::uint8_t>();
  if (byte > 1) throw CheckpointError("a flag byte of " + std::to_string(byte) + " where 0 or 1 belongs");
  return byte == 1;
}

void CheckpointReader::read(void* data, std::size_t bytes) {
  in_.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
  if (static_cast<std::size_t>(in_.gcount()) != bytes) throw CheckpointError("the file ends early");
}

void write_state(CheckpointWriter& out, const State& s) {
  out.value(s.time_s), out.value(s.step);
  out.array(s.position), out.array(s.orientation), out.array(s.velocity), out.array(s.angular_velocity);
  out.array(s.applied_force), out.array(s.applied_torque), out.array(s.left_model);
  out.array(s.damping_scale);
  out.array(s.pairs), out.flag(s.pairs_changed), out.array(s.position_at_rebuild);
  out.flag(s.pairs_valid);
  s.contacts.for_each_array([&](const auto& v) { out.array(v); });
  out.value(s.energy), out.value(s.last_gravitational_j), out.value(s.last_elastic_j);
  out.flag(s.energy_started);
  out.value(s.profile);
}

void read_state(CheckpointReader& in, State& s) {
  s.time_s = in.value<double>();
  s.step = in.value<long>();
  in.array(s.position), in.array(s.orientation), in.array(s.velocity), in.array(s.angular_velocity);
  in.array(s.applied_force), in.array(s.applied_torque), in.array(s.left_model);
  in.array(s.damping_scale);
  in.array(s.pairs);
  s.pairs_changed = in.flag();
  in.array(s.position_at_rebuild);
  s.pairs_valid = in.flag();
  s.contacts.for_each_array([&](auto& v) { in.array(v); });
  s.energy = in.value<Energy>();
  s.last_gravitational_j = in.value<double>();
  s.last_elastic_j = in.value<double>();
  s.energy_started = in.flag();
  s.profile = in.value<Profile>();
  s.gather_index_valid = false;  // the gather index follows the restored pair list
}

void write_joints(CheckpointWriter& out, const Joints& joints) {
  for_each_array(const_cast<Joints&>(joints), [&](const auto& v) { out.array(v); });
}

void read_joints(CheckpointReader& in, Joints& joints) {
  for_each_array(joints, [&](auto& v) { in.array(v); });
}

}  // namespace ishibashi
