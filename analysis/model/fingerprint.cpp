#include "analysis/model/fingerprint.h"

#include <fstream>
#include <sstream>

#include "io/scenario_file.h"

namespace ishibashi {

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::uint64_t program_fingerprint() {
  static const std::uint64_t h = fnv1a(file_bytes("/proc/self/exe"));
  return h;
}

std::uint64_t scenario_fingerprint(const std::filesystem::path& scenario_file) {
  return scenario_fingerprint(read_scenario(scenario_file));
}

std::uint64_t scenario_fingerprint(const Scenario& sc) {
  std::uint64_t h = fnv1a(file_bytes(sc.file));
  h = fnv1a(file_bytes(sc.model_file), h);
  for (const auto& c : sc.ground_motion.component)
    if (c) h = fnv1a(file_bytes(c->file), h);
  return h;
}

}  // namespace ishibashi
