// Binary snapshots of everything a step carries to the next (State) and of the joints,
// for checkpoints that resume a run bit-identically. Work buffers that each step rebuilds
// (poses, chunks, cell lists, the gather index) are not stored. The layout is the
// program's own (raw arrays): a checkpoint is read back only by the program that wrote it
// (the caller checks that; analysis/seismic_run.cpp).
#pragma once
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/joints.h"
#include "engine/state.h"

namespace ishibashi {

class CheckpointWriter {
 public:
  explicit CheckpointWriter(std::ostream& out) : out_(out) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>, "flags go through flag()");
    out_.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  // A bool as one byte, 0 or 1 (a damaged byte read back as a bool would be undefined).
  void flag(bool v) { value<std::uint8_t>(v ? 1 : 0); }
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
  explicit CheckpointReader(std::istream& in);
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>, "flags go through flag()");
    T v;
    read(&v, sizeof(T));
    return v;
  }
  bool flag();  // throws unless the byte is 0 or 1
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

void write_state(CheckpointWriter& out, const State& state);
// Overwrites what write_state stored; marks the derived buffers for rebuilding.
void read_state(CheckpointReader& in, State& state);

void write_joints(CheckpointWriter& out, const Joints& joints);
void read_joints(CheckpointReader& in, Joints& joints);

}  // namespace ishibashi
