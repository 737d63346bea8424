// Every preset scenario (Nishida A-F, dry and with mortar) run through the whole program
// path (model file, CGAL validation, settling, the Kobe record through the ground) ends in
// the state hash recorded in tests/data/. A refactor must keep every hash bit for bit; a
// physics change records new hashes in the same commit and says what it moved.
//
// Each line: preset, state hash, steps, motion hash (the blocks' part of the state; lines
// recorded before it have three fields).
//
// Two lengths: `Short` (0.005 s of settling, 0.005 s of the strongest pulses: contacts found,
// bonds made, the ground driven) runs with every test; `AfterSettlingAndKobe` (settling as
// the scenario says, then 0.2 s of Kobe from the scenario's start) takes about half an hour
// on two cores and runs with `ctest -L long` (scripts/preset_hashes.sh). Either prints the
// lines of its file, so that a physics change records them from the output.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "analysis/run/seismic_run.h"

namespace ishibashi {
namespace {

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;
const char* const kPresets[] = {"nishida_a_kobe_dry", "nishida_a_kobe_mortar", "nishida_b_kobe_dry", "nishida_b_kobe_mortar",
                                "nishida_c_kobe_dry", "nishida_c_kobe_mortar", "nishida_d_kobe_dry", "nishida_d_kobe_mortar",
                                "nishida_e_kobe_dry", "nishida_e_kobe_mortar", "nishida_f_kobe_dry", "nishida_f_kobe_mortar"};

// "preset hash steps" lines of a recorded file, by preset.
std::map<std::string, std::string> read_recorded(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::map<std::string, std::string> recorded;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string preset;
    fields >> preset;
    recorded[preset] = line;
  }
  return recorded;
}

// Runs every preset with the given settling limit (< 0: the scenario's) and shaking, from
// the record's `start_s` (< 0: the scenario's), and compares "preset hash steps" with the file.
void expect_recorded_hashes(const std::string& file_name, double settle_max_s, double shake_s, double start_s) {
  const auto recorded = read_recorded(kRoot / "tests/data" / file_name);
  EXPECT_EQ(recorded.size(), std::size(kPresets)) << "tests/data/" << file_name << " lists every preset once";
  std::string lines;
  for (const char* preset : kPresets) {
    Scenario sc = read_scenario(kRoot / "scenarios" / (std::string(preset) + ".toml"));
    if (settle_max_s >= 0) sc.settings.settle_max_s = settle_max_s;
    if (start_s >= 0) sc.settings.start_s = start_s;
    sc.settings.duration_s = shake_s;
    sc.settings.threads = 0;
    SeismicRunOptions options;
    options.out = std::filesystem::temp_directory_path() / preset;
    const SeismicRunResult r = SeismicRun(sc, options).run();
    std::ostringstream line;
    line << preset << " " << std::hex << r.state_hash << std::dec << " " << r.steps;
    const std::string without_motion = line.str();
    line << " " << std::hex << r.motion_hash << std::dec;
    lines += line.str() + "\n";
    // The motion hash tells moved blocks from a changed set of open points (World::motion_hash).
    // A line recorded before it was (three fields) is compared without it.
    const std::string expected = recorded.count(preset) ? recorded.at(preset) : "(none)";
    const bool has_motion = std::count(expected.begin(), expected.end(), ' ') == 3;
    EXPECT_EQ(has_motion ? line.str() : without_motion, expected)
        << "the state of " << preset << " changed (motion hash " << std::hex << r.motion_hash << std::dec
        << (has_motion ? "" : ", not recorded") << ")";
  }
  std::printf("%s", lines.c_str());
}

TEST(PresetHashes, Short) { expect_recorded_hashes("preset_hashes_short.txt", 0.005, 0.005, 7.6); }

TEST(PresetHashes, AfterSettlingAndKobe) { expect_recorded_hashes("preset_hashes.txt", -1, 0.2, -1); }

}  // namespace
}  // namespace ishibashi
