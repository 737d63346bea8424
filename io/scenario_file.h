// Scenario files (TOML): which model, which ground motion, how to run and what to
// record. Paths are relative to the scenario file. Errors name the file, line and key.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/ground_motion.h"
#include "io/model_file.h"

namespace ishibashi {

struct Scenario {
  std::filesystem::path file;          // the scenario file itself
  std::filesystem::path model_file;    // [model] file
  ModelFile model;
  double mortar_pa = -1.0;             // [model] mortar_pa; < 0: as the model file says
  bool bonds_when_settled = true;      // [model] mortar_bonds = "settled" (true) or "initial"
                                       // (ModelOptions::bonds_when_settled)
  double dt_s = 0.0;                   // [run] dt_s; 0: a share of the stability limit
                                       // (kStudyDtShare, kCappedDtShare in seismic_run.h)
  double settle_max_s = 1.0;           // [run] longest gravity settling
  double settle_kinetic_j = 1e-3;      // [run] settled when the kinetic energy is below
  double duration_s = 0.0;             // [run] shaking time; 0: the whole ground motion
  double output_interval_s = 0.05;     // [run] ParaView frames and history rows
  int threads = 0;                     // [run] 0: all cores
  int subdivision = 1;                 // [run] contact subdivision
  JointRule joint_rule = JointRule::corners;  // [run] joint_rule = "corners" or "moments" (model.h)
  ShearSpring shear_spring = ShearSpring::shear_modulus;  // [run] shear_spring = "shear_modulus" or "normal"
  Damping damping = Damping::study;    // [run] damping = "study", "capped" or "implicit"
  GroundMotionSpec ground_motion;      // [ground_motion] x, y, z = { file, format, scale, unit, dt_s }
  std::vector<int> monitor_blocks;     // [monitor] blocks; empty: the unit on top of the crown
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
