#include "analysis/run/checkpoint.h"

#include <algorithm>

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
  s.contacts_dead = static_cast<int>(s.contacts.size());  // the entries in no pair's range
  for (const Pair& pair : s.pairs) s.contacts_dead -= pair.sub_count;
}

}  // namespace ishibashi
