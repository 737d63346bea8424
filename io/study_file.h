// Study files (TOML): the models whose natural frequencies are wanted, the scenarios to
// run, and what the report shows; a [quick] table gives the short version CI runs.
// Paths are relative to the study file. Errors name the file, line and key.
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ishibashi {

struct StudyFile {
  std::filesystem::path file;
  std::string name;                               // [study] name, the report's title
  std::vector<std::filesystem::path> models;      // [study] models: modal and impulse analysis
  std::vector<std::filesystem::path> scenarios;   // [study] scenarios: seismic runs
  std::vector<double> snapshot_times_s;           // [study] seconds of shaking rendered in the report
  double duration_s = -1;                         // [study] seconds of shaking; < 0: each scenario's
  int members = 0;                                // [study] each run as an ensemble of this many
                                                  // members (analysis/batch/ensemble.h); 0: single runs
  int modes = 12;                                 // [frequencies] modes
  double impulse_s = 1.0;                         // [frequencies] impulse response length, s
  std::vector<std::string> joint_rules;           // [frequencies] each model under each of these
                                                  // rules; empty: the model's (scenario's) own
  // What the published study reports, shown beside this program's results in the report:
  // [reference.frequencies_hz] model file stem = [x, y, z], its first natural frequencies;
  // [reference.says] scenario file stem = "what the study says of that run".
  std::map<std::string, std::array<double, 3>> reference_frequencies_hz;
  std::map<std::string, std::string> reference_says;
  // [reference.outcome] scenario file stem = "collapse", "stands" or "no_stone_falls": its
  // verdict, so that the report gives the probability of the study's outcome.
  std::map<std::string, std::string> reference_outcome;
};

// With quick = true, the keys of [quick] (models, scenarios, snapshot_times_s,
// duration_s, modes, impulse_s) replace the others.
StudyFile read_study(const std::filesystem::path& file, bool quick);

}  // namespace ishibashi
