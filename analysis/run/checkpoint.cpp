#include "analysis/run/checkpoint.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "analysis/model/fingerprint.h"
#include "geometry/input_error.h"
#include "io/atomic_file.h"

namespace ishibashi {

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

void write_state(CheckpointWriter& out, const State& s) { visit_state(out, s); }

void read_state(CheckpointReader& in, State& s) {
  visit_state(in, s);
  s.pair_index_valid = false;  // the pair indices follow the restored pair list
  forget_step_motion(s);  // the blocks' step motions are not in the checkpoint
  // Each array of the sub-contacts is read with its own length: all must be the keys'.
  s.contacts.for_each_named_array([&](const char* name, const auto& array) {
    if (array.size() != s.contacts.size())
      throw CheckpointError(std::string("the sub-contacts' ") + name + " holds " + std::to_string(array.size()) + " entries, their keys " +
                            std::to_string(s.contacts.size()));
  });
  // Each pair's range must lie within the sub-contacts read (the checksum guards against
  // damage, not against a body made by hand): the step indexes them unchecked.
  const auto contacts = static_cast<std::int64_t>(s.contacts.size());
  std::int64_t dead = contacts;  // the entries in no pair's range
  for (std::size_t p = 0; p < s.pairs.size(); ++p) {
    const std::int64_t begin = s.pairs[p].sub_begin, count = s.pairs[p].sub_count;
    if (count < 0 || (count > 0 && (begin < 0 || begin + count > contacts)))
      throw CheckpointError("pair " + std::to_string(p) + " names sub-contacts " + std::to_string(begin) + " to " +
                            std::to_string(begin + count - 1) + " of the " + std::to_string(contacts) + " written");
    dead -= count;
  }
  if (dead < 0) throw CheckpointError("the pairs' ranges overlap: they name more sub-contacts than the " + std::to_string(contacts) + " written");
  s.contacts_dead = static_cast<int>(dead);
}

namespace {

// "pair 3 (blocks 4 and 9)" for the messages below.
std::string pair_label(std::size_t p, const Pair& pair) {
  return "pair " + std::to_string(p) + " (blocks " + std::to_string(pair.a) + " and " + std::to_string(pair.b) + ")";
}

}  // namespace

void check_state_fits(const State& s, const Model& m) {
  const int nb = m.block_count;
  auto sized = [](const char* what, std::size_t size, std::size_t wanted) {
    if (size != wanted)
      throw CheckpointError(std::string(what) + " holds " + std::to_string(size) + " entries where the model has " + std::to_string(wanted));
  };
  const std::size_t blocks = static_cast<std::size_t>(nb), ties = m.ties.size();
  sized("the blocks' positions", s.position.size(), blocks), sized("orientations", s.orientation.size(), blocks);
  sized("velocities", s.velocity.size(), blocks), sized("angular velocities", s.angular_velocity.size(), blocks);
  sized("driven velocities", s.driven_velocity.size(), blocks), sized("driven angular velocities", s.driven_angular_velocity.size(), blocks);
  sized("applied forces", s.applied_force.size(), blocks), sized("applied torques", s.applied_torque.size(), blocks);
  sized("left_model", s.left_model.size(), blocks), sized("damping scales", s.damping_scale.size(), blocks);
  sized("positions at the last broadphase", s.position_at_rebuild.size(), blocks);
  sized("the ground's carried forces", s.prescribed_force_carried.size(), blocks);
  sized("the ground's carried moments", s.prescribed_moment_carried.size(), blocks);
  sized("the tie rods' elongations", s.tie_plastic_m.size(), ties), sized("tie tensions", s.tie_tension_n.size(), ties);
  sized("peak tie tensions", s.tie_peak_tension_n.size(), ties);
  // The blocks' motion: finite, orientations unit (the broadphase bins positions into cells
  // before the step could find a NaN, and the pose takes each quaternion as a rotation).
  if (!std::isfinite(s.time_s)) throw CheckpointError("its time is not a finite number");
  for (int b = 0; b < nb; ++b) {
    const Quat& q = s.orientation[b];
    const bool finite = s.position[b].allFinite() && q.coeffs().allFinite() && s.velocity[b].allFinite() &&
                        s.angular_velocity[b].allFinite();
    if (!finite || std::abs(q.norm() - 1) > 1e-9)
      throw CheckpointError(m.block_label(b) + (finite ? "'s orientation is no unit quaternion (norm " + std::to_string(q.norm()) + ")"
                                                       : "'s position, orientation or velocity is not a finite number"));
  }
  // The pairs: blocks a < b of the model, in (a, b) order without repeats (the broadphase
  // merges against that order), the remembered axis a face of its own block, and the
  // sub-contacts in its range between its own blocks (the step indexes all of these unchecked).
  for (std::size_t p = 0; p < s.pairs.size(); ++p) {
    const Pair& pair = s.pairs[p];
    if (pair.a < 0 || pair.a >= pair.b || pair.b >= nb)
      throw CheckpointError(pair_label(p, pair) + ": a pair joins two blocks a < b of the model's " + std::to_string(nb));
    if (p > 0 && std::pair(s.pairs[p - 1].a, s.pairs[p - 1].b) >= std::pair(pair.a, pair.b))
      throw CheckpointError(pair_label(p, pair) + " follows " + pair_label(p - 1, s.pairs[p - 1]) + ": the pairs are listed once each, in order");
    if (pair.axis_kind < -1 || pair.axis_kind > 2)
      throw CheckpointError(pair_label(p, pair) + ": axis kind " + std::to_string(pair.axis_kind) + " where -1 to 2 belong");
    if (pair.axis_kind == 0 || pair.axis_kind == 1) {
      const int owner = pair.axis_kind == 0 ? pair.a : pair.b, stone = pair.axis_kind == 0 ? pair.b : pair.a;
      const int f = pair.axis_feature;
      if (f < m.face_begin[owner] || f >= m.face_begin[owner + 1])
        throw CheckpointError(pair_label(p, pair) + ": face " + std::to_string(f) + " is no face of block " + std::to_string(owner));
      const int lines = m.face_vertex_begin[f + 1] - m.face_vertex_begin[f] + m.direction_begin[stone + 1] - m.direction_begin[stone];
      if (pair.beside_axis < -1 || pair.beside_axis >= lines)
        throw CheckpointError(pair_label(p, pair) + ": line " + std::to_string(pair.beside_axis) + " beside its face, of " + std::to_string(lines));
    }
    for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i)
      if (s.contacts.block_a[i] != pair.a || s.contacts.block_b[i] != pair.b)
        throw CheckpointError(pair_label(p, pair) + ": its sub-contact " + std::to_string(i) + " joins blocks " +
                              std::to_string(s.contacts.block_a[i]) + " and " + std::to_string(s.contacts.block_b[i]));
  }
  sized("the ground's forces before", s.prescribed_entry_force_before.size(), s.prescribed_entry.size());
  sized("the ground's moments before", s.prescribed_entry_moment_before.size(), s.prescribed_entry.size());
  for (const auto& [entry, block] : s.prescribed_entry)
    if (block < 0 || block >= nb || m.motion[block] != Motion::prescribed)
      throw CheckpointError("the ground's forces name block " + std::to_string(block) + ", which is no prescribed block of the model");
}

void check_joints_fit(const Joints& read, const Joints& found) {
  // The joints are found anew from the model's first contacts before a resume: the same
  // joints, each with its points, or the checkpoint is another model's.
  if (read.block_a != found.block_a || read.block_b != found.block_b || read.point_begin != found.point_begin)
    throw CheckpointError("its " + std::to_string(read.size()) + " joints are not the model's " + std::to_string(found.size()));
  const std::size_t nj = found.block_a.size(), nq = found.point_on_a.size();
  for (std::size_t size : {read.point_on_a.size(), read.point_on_b.size(), read.reference_on_a.size()})
    if (size != nq) throw CheckpointError("a joint array holds " + std::to_string(size) + " points of the joints' " + std::to_string(nq));
  for (std::size_t size : {read.centre_on_a.size(), read.centre_on_b.size(), read.normal_on_a.size(), read.centre_reference_on_a.size(),
                           read.opening_m.size(), read.slip_m.size(), read.broken_at_reference.size(), read.bond_broken.size(),
                           read.cracked.size()})
    if (size != nj) throw CheckpointError("a joint array holds " + std::to_string(size) + " entries for the " + std::to_string(nj) + " joints");
}

namespace {

// 11: the body's FNV-1a checksum after the header (a damaged byte was resumed from silently).
// 12: each pair's bound on its relative motion (Pair::moved_bound_m).
// 13: the run's wall time spent recording frames (SeismicRunResult::output_wall_s).
// 14: each pair's motion bound below which its empty face manifold stays empty (Pair::clear_below_m).
// 15: each empty face pair's allowance, how far it may move before it is clipped again
//     (Pair::clear_for_m, in place of 14's bound), and the line that held its stone beside
//     the face (Pair::beside_axis).
// 16: the run's motion hash (SeismicRunResult::motion_hash).
// 17: the bond utilisation's peak until the first crack (SeismicRunResult::bond_utilisation_peak).
// 18: its largest sample since the last frame, and whether bonds are left (history.csv's
//     bond_utilisation is the frame interval's peak).
// 19: the prescribed blocks' contact forces at the previous pose (per block:
//     the ground's work by the trapezoid rule).
// 20: those forces per pair side, so that the pass that wrote them sums the ground's work
//     (State::prescribed_entry_force_before), and per block for the sides no longer listed.
// 21: each apart pair's reading of the apart clock below which it is left unvisited
//     (Pair::apart_until_clock_m); the clock is not kept: a restored run's first pose does
//     not know its step turns, so its narrowphase visits every pair and schedules them anew.
// 22: the tie rods' plastic elongations, tensions and peak tensions; Energy::tie_yield_j.
// 23: the run's result holds the rods' count, how many yielded and their peak tension.
// 24: the result says whether the run stopped early and how it fails (its failure mode);
//     the outputs keep when and which way each stone fell (how_it_fails.h, FallRecord).
// 25: the ring's hinges until its first stone fell (how_it_fails.h, RingHinges) and the
//     result's most_ring_hinges.
// 26: the prescribed blocks' velocities for the step ahead (State::driven_velocity).
// 27: the energy made by re-clipped pairs' springs (Energy::reclip_j); the result's share.
constexpr char kCheckpointMagic[] = "ishibashi checkpoint 27\n";

template <class Archive, class H>
void visit_header(Archive& a, H& h) {
  a.field(h.program), a.field(h.inputs), a.field(h.scenario_file);
  for_each_run_setting([&](const SettingInfo&, auto member) { a.field(h.settings.*member); });
  a.field(h.member);
}

}  // namespace

void write_checkpoint_file(const std::filesystem::path& file, const CheckpointHeader& header, const std::string& body) {
  write_atomically(file, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    CheckpointWriter w(out);
    w.text(kCheckpointMagic);
    visit_header(w, header);
    w.value<std::uint64_t>(fnv1a(body));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(errno));
  });
}

CheckpointHeader read_checkpoint_file(const std::filesystem::path& file, std::string* body) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": no checkpoint to resume from (run with --checkpoint-every or --checkpoint-wall)");
  CheckpointHeader h;
  try {
    CheckpointReader reader(in);
    if (reader.text() != kCheckpointMagic) throw InputError(file.string() + ": not a checkpoint of this program");
    visit_header(reader, h);
    const auto checksum = reader.value<std::uint64_t>();
    body->assign(std::istreambuf_iterator<char>(in), {});
    if (fnv1a(*body) != checksum) throw CheckpointError("its contents differ from the checksum written with them");
  } catch (const CheckpointError& e) {
    throw InputError(file.string() + ": damaged checkpoint (" + e.what() + ")");
  }
  return h;
}

}  // namespace ishibashi
