#include "analysis/run/checkpoint.h"

#include <algorithm>
#include <cerrno>
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
constexpr char kCheckpointMagic[] = "ishibashi checkpoint 26\n";

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
