// Binary snapshots of everything a step carries to the next (State) and of the joints,
// for checkpoints that resume a run bit-identically. Work buffers that each step rebuilds
// (poses, chunks, cell lists, the gather index) are not stored. The layout is the
// program's own (raw arrays): a checkpoint is read back only by the program that wrote it
// (the caller checks that; analysis/seismic_run.cpp).
#pragma once
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/joints.h"
#include "engine/state.h"
#include "io/run_settings.h"

namespace ishibashi {

template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};

// Writer and reader share field(): one visitor function lists what a checkpoint holds, in
// one order, and serves both (visit_state below, the run's progress in seismic_run.cpp).
class CheckpointWriter {
 public:
  static constexpr bool reading = false;
  explicit CheckpointWriter(std::ostream& out) : out_(out) {}
  template <class T>
  void field(const T& v) {
    if constexpr (std::is_same_v<T, bool>) flag(v);
    else if constexpr (std::is_same_v<T, std::string>) text(v);
    else if constexpr (is_vector<T>::value) array(v);
    else value(v);
  }
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>, "flags go through flag()");
    out_.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  // A bool as one byte, 0 or 1 (a damaged byte read back as a bool would be undefined).
  void flag(bool v) { value<std::uint8_t>(v ? 1 : 0); }
  void flag_read_whole(const bool&, const char*) {}  // the reader checks it
  template <class T>
  void array(const std::vector<T>& v) {
    value<std::uint64_t>(v.size());
    out_.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(sizeof(T) * v.size()));
  }
  void text(const std::string& s) {
    value<std::uint64_t>(s.size());
    out_.write(s.data(), static_cast<std::streamsize>(s.size()));
  }

 private:
  std::ostream& out_;
};

// Throws CheckpointError when the stream ends early or a size is implausible.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CheckpointReader {
 public:
  static constexpr bool reading = true;
  explicit CheckpointReader(std::istream& in);
  template <class T>
  void field(T& v) {
    if constexpr (std::is_same_v<T, bool>) v = flag();
    else if constexpr (std::is_same_v<T, std::string>) v = text();
    else if constexpr (is_vector<T>::value) array(v);
    else v = value<T>();
  }
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>, "flags go through flag()");
    T v;
    read(&v, sizeof(T));
    return v;
  }
  bool flag();  // throws unless the byte is 0 or 1
  // A bool inside a struct read whole (the Profile's): its byte too must be 0 or 1.
  void flag_read_whole(const bool& v, const char* what) {
    std::uint8_t byte;
    std::memcpy(&byte, &v, 1);
    if (byte > 1) throw CheckpointError(std::string(what) + " is the byte " + std::to_string(byte) + " where 0 or 1 belong");
  }
  template <class T>
  void array(std::vector<T>& v) {
    v.resize(size(sizeof(T)));
    read(v.data(), sizeof(T) * v.size());
  }
  std::string text() {
    std::string s(size(1), '\0');
    read(s.data(), s.size());
    return s;
  }

 private:
  std::size_t size(std::size_t element_bytes);
  void read(void* data, std::size_t bytes);
  std::istream& in_;
  std::streamoff end_ = 0;  // the stream's length: no array may claim more bytes than are left
};

// Everything a step carries to the next, for CheckpointWriter (S = const State) and
// CheckpointReader (S = State).
template <class Archive, class S>
void visit_state(Archive& a, S& s) {
  a.field(s.time_s), a.field(s.step);
  a.field(s.position), a.field(s.orientation), a.field(s.velocity), a.field(s.angular_velocity);
  a.field(s.driven_velocity), a.field(s.driven_angular_velocity);
  a.field(s.applied_force), a.field(s.applied_torque), a.field(s.left_model);
  a.field(s.damping_scale);
  a.field(s.implicit.delta), a.field(s.implicit.diagonal);  // first guess, preconditioner (Damping::implicit)
  a.field(s.pairs), a.field(s.pairs_changed), a.field(s.position_at_rebuild);
  a.field(s.pairs_valid);
  s.contacts.for_each_array([&](auto& array) { a.field(array); });
  a.field(s.energy), a.field(s.last_gravitational_j), a.field(s.last_elastic_j);
  // The ground's forces at the pose before: the list of sides they follow, so that the
  // rebuilt list (the same) keeps them.
  a.field(s.prescribed_entry), a.field(s.prescribed_entry_force_before), a.field(s.prescribed_entry_moment_before);
  a.field(s.prescribed_force_carried), a.field(s.prescribed_moment_carried);
  a.field(s.energy_started);
  a.field(s.tie_plastic_m), a.field(s.tie_tension_n), a.field(s.tie_peak_tension_n);
  a.field(s.profile), a.flag_read_whole(s.profile.threads_timed, "the profile's flag of timed threads");
}

template <class Archive, class J>
void visit_joints(Archive& a, J& j) {
  a.field(j.block_a), a.field(j.block_b), a.field(j.point_begin), a.field(j.point_on_a), a.field(j.point_on_b);
  a.field(j.centre_on_a), a.field(j.centre_on_b), a.field(j.normal_on_a), a.field(j.reference_on_a);
  a.field(j.centre_reference_on_a), a.field(j.opening_m), a.field(j.slip_m), a.field(j.broken_at_reference);
  a.field(j.bond_broken), a.field(j.cracked);
}

void write_state(CheckpointWriter& out, const State& state);
// Overwrites what write_state stored; marks the derived buffers for rebuilding.
void read_state(CheckpointReader& in, State& state);
// Throws CheckpointError unless a state read back fits `model`: its arrays sized for the
// model's blocks and rods, its pairs, faces and sub-contacts naming the model's (a body
// made by hand passes the checksum, and the step indexes them unchecked).
void check_state_fits(const State& state, const Model& model);
// Likewise unless the joints read back are those `found` in the model (engine/joints.h).
void check_joints_fit(const Joints& read, const Joints& found);

// What the checkpoint's run was: the program, the input files and the run's settings
// (command-line overrides included, dt_s the step it used), so that a resume rebuilds the same run.
struct CheckpointHeader {
  std::uint64_t program = 0, inputs = 0;
  std::string scenario_file;
  RunSettings settings;
  int member = -1;  // of the scenario's ensemble
};

// checkpoint.bin: a magic line, the header, the body's FNV-1a checksum (a resume must not
// go on from a damaged state), then the body (the run's progress and its State, written by
// the caller). Written atomically: a full disk leaves the last checkpoint as it was.
void write_checkpoint_file(const std::filesystem::path& file, const CheckpointHeader& header, const std::string& body);
// Reads one back into *body; throws InputError naming `file` when it is another program's,
// or damaged (cut short, or its body no longer matches the checksum written with it).
CheckpointHeader read_checkpoint_file(const std::filesystem::path& file, std::string* body);


}  // namespace ishibashi
