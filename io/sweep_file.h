// Sweep files (TOML): one scenario (the model, its damping, settling) or several variants
// of it to compare (dry and with mortar, a retrofit), any number of three-component
// ground-motion records, intensity levels (target PGAs or scale factors) and what counts
// as failure. `ishibashi sweep` runs every (scenario, record, level): an incremental
// dynamic analysis per record and a fragility curve per scenario over all of them.
// Paths are relative to the sweep file. Errors name the file, line and key.
//
//   [sweep]
//   scenario = "nishida_a_kobe_dry.toml"       # or, to compare variants on the same records:
//   # scenarios = ["nishida_a_kobe_dry.toml", "nishida_a_kobe_mortar.toml"]
//   duration_s = 10            # seconds of shaking (default: the scenario's)
//   pga_g = [0.2, 0.4, 0.6]    # scale each record to these PGAs (larger horizontal), or
//   # scale = [0.5, 1.0]       # multiply each record by these factors
//   [failure]                  # any of these is failure (at least one must be set)
//   collapse = true            # a ring stone fell, or more than 5 % of the blocks
//   crown_drop_m = 0.05        # the crown unit dropped by more than this
//   fallen_stones = 10         # at least this many stones fell
//   stop_at_failure = true     # each run ends at its first frame that has failed (default false)
//   [[record]]
//   name = "kobe_jma"
//   start_s = 4.0
//   x = { file = "...", format = "at2" }   # as a scenario's [ground_motion]
//   y = { ... }
//   z = { ... }
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/ground_motion.h"

namespace ishibashi {

struct SweepRecord {
  std::string name;          // letters, digits, '_', '-' and '.': it names the run folders
  GroundMotionSpec motion;   // components and start_s; scale 1 (the sweep scales)
};

struct FailureCriteria {
  bool collapse = true;
  double crown_drop_m = -1;  // < 0: not a criterion
  int fallen_stones = -1;    // < 0: not a criterion
  // End a run at its first output frame that meets a criterion: its verdict cannot change
  // after (a fallen stone does not climb back, the crown drop is the largest so far), and a
  // collapse's debris, the rest of such a run, is its costliest part. The IDA curves then
  // show a failed run's crown drop where it stopped.
  bool stop_at_failure = false;
};

struct SweepFile {
  std::filesystem::path file;
  // Each named by its file's stem (unique): the first is the reference the others are
  // compared with.
  std::vector<std::filesystem::path> scenarios;
  double duration_s = -1;        // < 0: the scenario's
  // [sweep] members: each (scenario, record, level) as this many ensemble members (the
  // scenario's [ensemble] seed and tolerance, analysis/run/member_draw.h), more samples per
  // level for the fragility fit; <= 1: the scenario's own run.
  int members = 1;
  bool scale_to_pga = true;      // levels are target PGAs in g; false: scale factors
  std::vector<double> levels;
  FailureCriteria failure;
  std::vector<SweepRecord> records;
};

SweepFile read_sweep(const std::filesystem::path& file);

// An intensity level as it names its runs' folders and the rows of sweep.csv ("%g": 0.25,
// 1.5, 1e-05); read_sweep refuses two levels of one label.
std::string level_label(double level);

}  // namespace ishibashi
