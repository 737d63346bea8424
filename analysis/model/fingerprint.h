// Fingerprints of what a result depends on: the program itself (a rebuilt engine makes
// every output stale) and the input files of a scenario. FNV-1a, 64 bits: for telling
// versions apart, not for security.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

namespace ishibashi {

struct Scenario;

std::string file_bytes(const std::filesystem::path& file);
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 1469598103934665603ull);
std::uint64_t program_fingerprint();
// The scenario file, its model file and its ground-motion records.
std::uint64_t scenario_fingerprint(const std::filesystem::path& scenario_file);
std::uint64_t scenario_fingerprint(const Scenario& scenario);  // read from scenario.file

}  // namespace ishibashi
