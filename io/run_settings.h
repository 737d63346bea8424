// The settings of a seismic run, declared once (for_each_run_setting): the scenario file's
// keys and their checks, the command line's overrides (apps/run_setting_flags.h), a
// checkpoint's header and summary.json's "settings" are all made from the one list below.
// Adding a setting: a field of RunSettings and a line of the list (and, when it changes the
// model, a line of model_options).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <type_traits>

#include "engine/cores.h"
#include "engine/model.h"

namespace ishibashi {

// When mortar sets: in the settled pose (ModelOptions::bonds_when_settled) or from the
// first step of the settling.
enum class MortarBonds : std::uint8_t { initial, settled };
inline constexpr std::array<const char*, 2> kMortarBondsNames{"initial", "settled"};
inline const auto& choice_names(MortarBonds) { return kMortarBondsNames; }

// Where a seismic run ends: at the record's end (its duration), or at its first output
// frame that finds it collapsed (SeismicRunResult::collapse). A collapse cannot be undone
// (a fallen stone does not climb back) and its debris is the costliest part of a run, so an
// ensemble that asks only how likely a collapse is stops each collapsing member there; what
// it counts of such a member (fallen stones, crown drop) is then at the collapse.
enum class StopAt : std::uint8_t { end, collapse };
inline constexpr std::array<const char*, 2> kStopAtNames{"end", "collapse"};
inline const auto& choice_names(StopAt) { return kStopAtNames; }

struct RunSettings {
  double dt_s = 0.0;                // 0: a share of the stability limit (kStudyDtShare ... in seismic_run.h)
  double settle_max_s = 1.0;        // longest gravity settling
  double settle_kinetic_j = 1e-3;   // settled when the kinetic energy is below this
  double duration_s = 0.0;          // shaking time; 0: the whole ground motion
  double start_s = 0.0;             // skip this much of the record
  double output_interval_s = 0.05;  // ParaView frames and history rows
  int threads = 0;                  // 0: all cores
  int subdivision = 1;              // contact subdivision (ModelOptions)
  JointRule joint_rule = JointRule::corners;
  ShearSpring shear_spring = ShearSpring::shear_modulus;
  Damping damping = Damping::study;
  double solve_tolerance = kDampingSolveTolerance;  // Damping::implicit (ModelOptions)
  MortarBonds mortar_bonds = MortarBonds::settled;
  StopAt stop_at = StopAt::end;
};

// Where a setting lives in a scenario file, its command-line flag (nullptr: none), what it
// means and the range of a number (min excluded when open_min).
struct SettingInfo {
  const char* table;
  const char* key;
  const char* flag;
  const char* help;
  double min = -INFINITY, max = INFINITY;
  bool open_min = false;
};

// Calls fn(info, member) for every setting, member a pointer to its RunSettings field, in
// one order (the checkpoint header's).
template <class Fn>
void for_each_run_setting(Fn&& fn) {
  using S = RunSettings;
  constexpr double inf = INFINITY;
  fn(SettingInfo{"run", "dt_s", "--dt", "time step, s (0: a share of the stability limit)", 0, inf}, &S::dt_s);
  fn(SettingInfo{"run", "settle_max_s", "--settle-max", "longest gravity settling, s", 0, inf}, &S::settle_max_s);
  fn(SettingInfo{"run", "settle_kinetic_j", "--settle-kinetic", "settled when the kinetic energy is below this, J", 0, inf},
     &S::settle_kinetic_j);
  fn(SettingInfo{"run", "duration_s", "--duration", "seconds of shaking (0: the whole record)", 0, inf}, &S::duration_s);
  fn(SettingInfo{"ground_motion", "start_s", "--start", "where in the record the shaking starts, s", 0, inf}, &S::start_s);
  fn(SettingInfo{"run", "output_interval_s", "--output-interval", "ParaView frames and history rows every this many s", 0, inf,
                 true},
     &S::output_interval_s);
  fn(SettingInfo{"run", "threads", "--threads", "threads (0: every usable core)", 0, kMaxThreads}, &S::threads);
  fn(SettingInfo{"run", "subdivision", "--subdivision", "contact subdivision", 1, kMaxSubdivision}, &S::subdivision);
  fn(SettingInfo{"run", "joint_rule", "--joint-rule",
                 "joint points: \"corners\" (the study's corner contacts) or \"moments\" (corners, centroid and fan "
                 "centroids: a uniform bed's second moments)"},
     &S::joint_rule);
  fn(SettingInfo{"run", "shear_spring", "--shear-spring",
                 "joint shear spring: \"shear_modulus\" (K_s from G, MODEL.md) or \"normal\" (K_s = K_n)"},
     &S::shear_spring);
  fn(SettingInfo{"run", "damping", "--damping",
                 "dashpots: \"study\" (as specified; dt set by them), \"capped\" (scaled down where dt would not resolve "
                 "them; dt set by the springs) or \"implicit\" (as specified, integrated implicitly; dt set by the springs)"},
     &S::damping);
  fn(SettingInfo{"run", "solve_tolerance", "--solve-tolerance",
                 "implicit dashpots: the solve stops when its residual is this share of the dashpots' impulse", 0, 0.5,
                 true},
     &S::solve_tolerance);
  fn(SettingInfo{"model", "mortar_bonds", "--mortar-bonds",
                 "mortar sets \"settled\" (in the settled pose) or \"initial\" (from the first step)"},
     &S::mortar_bonds);
  fn(SettingInfo{"run", "stop_at", "--stop-at",
                 "where the run ends: \"end\" (the record's end) or \"collapse\" (its first frame that finds it collapsed, "
                 "where a collapse is known: the rest is debris; the counts are then those at the collapse)"},
     &S::stop_at);
}

// The settings as the inputs key of a run's outputs gives them (" key=value" each), the
// thread count left out: a run gives the same bits on any.
std::string settings_key_text(const RunSettings& settings);

// The model a run's settings ask for (with the ModelOptions defaults for the rest).
ModelOptions model_options(const RunSettings& settings);

// Settings given elsewhere than the scenario file (the command line, a study or sweep
// file, a checkpoint): the values of the keys in `given`.
struct RunOverrides {
  RunSettings values;
  std::set<std::string> given;  // SettingInfo::key

  template <class T>
  RunOverrides& set(T RunSettings::*member, T value) {
    values.*member = value;
    for_each_run_setting([&](const SettingInfo& info, auto m) {
      if constexpr (std::is_same_v<decltype(m), T RunSettings::*>)
        if (m == member) given.insert(info.key);
    });
    return *this;
  }
};

class TableReader;
// The settings that live in the scenario file's table `table` ("run", "model",
// "ground_motion"), checked; errors name the file, line and key.
void read_run_settings(TableReader& reader, const std::string& table, RunSettings& settings);

// settings with every given override in place.
void apply_overrides(RunSettings& settings, const RunOverrides& overrides);

// The setting's value as summary.json and messages give it: a number, or an enum's name.
template <class T>
auto setting_value(const T& v) {
  if constexpr (std::is_enum_v<T>) return std::string(choice_names(v)[static_cast<int>(v)]);
  else return v;
}

}  // namespace ishibashi
