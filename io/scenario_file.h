// Scenario files (TOML): which model, which ground motion, how to run and what to
// record. Paths are relative to the scenario file. Errors name the file, line and key.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "io/ground_motion.h"
#include "io/model_file.h"
#include "io/run_settings.h"

namespace ishibashi {

// [ensemble]: an ensemble of runs of one scenario, members that differ by what a real
// bridge is uncertain about (analysis/run/member_draw.h draws them).
struct EnsembleSpec {
  int members = 0;                 // 0: a single run of the scenario as written
  long seed = 1;                   // member i draws from (seed, i): the same members every time
  // Construction tolerance, drawn before settling: each free stone cut up to this much
  // smaller and placed within it, where it overlaps no neighbour (perturb_model in
  // analysis/run/member_draw.h). 0.1 mm: small against real masonry's millimetres, so that the
  // loosened joints settle the ring by little (a ring of 20 voussoirs shortens by about
  // 2 mm at most), yet each member's stones bear on different corners.
  double position_tolerance_m = 1e-4;
  std::array<double, 2> friction_angle_deg{0, 0};  // drawn uniformly in [lo, hi]; 0, 0: the materials'
  std::array<double, 2> amplitude{1, 1};           // the record's scale, drawn uniformly in [lo, hi]
  bool varies_friction() const { return friction_angle_deg[1] > 0; }
};

struct Scenario {
  std::filesystem::path file;          // the scenario file itself
  std::filesystem::path model_file;    // [model] file
  ModelFile model;                     // with the scenario's [model] mortar_pa and fracture energies
  RunSettings settings;                // [run], [model] mortar_bonds, [ground_motion] start_s (run_settings.h)
  GroundMotionSpec ground_motion;      // [ground_motion] x, y, z = { file, format, scale, unit, dt_s }, baseline_correction
  std::vector<int> monitor_blocks;     // [monitor] blocks; empty: the unit on top of the crown
  EnsembleSpec ensemble;               // [ensemble] members, seed, position_tolerance_m, friction_angle_deg, amplitude

  // The ground motion to run: the records over the settings' window.
  GroundMotionSpec motion() const {
    GroundMotionSpec spec = ground_motion;
    spec.start_s = settings.start_s;
    spec.duration_s = settings.duration_s;
    return spec;
  }
};

Scenario read_scenario(const std::filesystem::path& file);

class TableReader;
// The x, y and z = { file, format, unit, dt_s, scale } keys of a ground-motion table
// (paths relative to `base`), into spec.component; scenario and sweep files share them.
void read_ground_motion_components(TableReader& table, const std::filesystem::path& file, const std::filesystem::path& base,
                                   const std::string& name, GroundMotionSpec& spec);

// True when the file is a scenario (has [run] or [ground_motion]), false for a model file.
bool is_scenario_file(const std::filesystem::path& file);

}  // namespace ishibashi
