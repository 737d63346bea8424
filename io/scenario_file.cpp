#include "io/scenario_file.h"

#include "io/toml_reader.h"

namespace ishibashi {
namespace {

// `base / path`, the file that `what` (e.g. `[model] file`) of `file` names; one that does
// not exist is refused with where it was looked for. A scenario copied out of scenarios/
// alone is the usual cause: its ../models no longer lies beside it.
std::filesystem::path named_file(const std::filesystem::path& file, const std::filesystem::path& base,
                                 const std::string& what, const std::string& path) {
  const std::filesystem::path named = base / path;
  if (!std::filesystem::exists(named))
    throw InputError(file.string() + ": " + what + " = \"" + path + "\" is " + named.lexically_normal().string() +
                     ", which does not exist (a relative path starts at this file's folder, " + base.string() +
                     "; with a scenario copied elsewhere copy the models and data folders it names too, or give "
                     "absolute paths)");
  return named;
}

}  // namespace

void read_ground_motion_components(TableReader& table, const std::filesystem::path& file, const std::filesystem::path& base,
                                   const std::string& name, GroundMotionSpec& spec) {
  const char* axes[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    const toml::table* t = table.subtable(axes[c]);
    if (!t) continue;
    TableReader comp(file, t, name + "." + axes[c]);
    ComponentSpec cs;
    std::string path, unit = "g";
    comp.text("file", path);
    comp.text("format", cs.format, {"at2", "knet", "columns"});
    comp.text("unit", unit, {"g", "gal", "m/s2"});
    comp.non_negative("dt_s", cs.layout.dt_s);  // 0: the file's first column is time
    comp.integer_in("column", cs.layout.column, 1, 1000);
    comp.integer_in("header_lines", cs.layout.header_lines, 0, 1000000);
    comp.number("scale", cs.scale);
    comp.finish();
    if (path.empty()) throw InputError(file.string() + ": [" + name + "] " + axes[c] + " needs file = \"...\"");
    // An .AT2 or K-NET file says its own unit, step and layout: a setting for columns given
    // for one was read as nothing (unit = "gal" on an .AT2 file in g).
    if (cs.format != "columns" &&
        (cs.layout.column > 0 || cs.layout.header_lines > 0 || cs.layout.dt_s > 0 || t->contains("unit")))
      throw InputError(file.string() + ": [" + name + "] " + axes[c] + ": unit, dt_s, column and header_lines are for format = " +
                       "\"columns\" (" + cs.format + " files say their own unit, step and where their samples are)");
    cs.file = base / path;  // read when the run starts: a scenario may be read for its settings alone
    cs.unit = unit == "gal" ? AccelerationUnit::gal : unit == "m/s2" ? AccelerationUnit::m_s2 : AccelerationUnit::g;
    spec.component[c] = cs;
  }
}

bool is_scenario_file(const std::filesystem::path& file) {
  try {
    const toml::table root = toml::parse_file(file.string());
    return root.contains("run") || root.contains("ground_motion");
  } catch (const toml::parse_error&) {
    return false;  // reading it as a model file reports the error
  }
}

Scenario read_scenario(const std::filesystem::path& file) {
  const toml::table root = parse_toml_file(file, kScenarioFile);
  Scenario sc;
  sc.file = file;
  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();

  TableReader model(file, root, "model");
  std::string model_file;
  model.text("file", model_file);
  // -1 where absent: as the model file says; a negative value given is an error, not "absent".
  double mortar_pa = -1, tension_fracture = -1, shear_fracture = -1;
  model.non_negative("mortar_pa", mortar_pa);
  model.non_negative("mortar_tension_fracture_j_m2", tension_fracture);
  model.non_negative("mortar_shear_fracture_j_m2", shear_fracture);
  std::vector<Part> mortar_parts;  // empty where absent: as the model file says
  read_mortar_parts(model, mortar_parts);
  read_run_settings(model, "model", sc.settings);
  model.finish();
  if (model_file.empty()) throw InputError(file.string() + ": [model] file = \"...\" is required (a model file, e.g. models/nishida_a.toml)");
  sc.model_file = named_file(file, base, "[model] file", model_file);
  sc.model = read_model_file(sc.model_file);
  if (mortar_pa >= 0) sc.model.bridge.mortar_pa = mortar_pa;
  if (!mortar_parts.empty()) sc.model.bridge.mortar_parts = mortar_parts;
  if (tension_fracture >= 0 || shear_fracture >= 0) {
    sc.model.bridge.mortar_tension_fracture_j_m2 = std::max(0.0, tension_fracture);
    sc.model.bridge.mortar_shear_fracture_j_m2 = std::max(0.0, shear_fracture);
    require_both_fracture_energies(file, "[model]", sc.model.bridge);
  }

  TableReader run(file, root, "run");
  read_run_settings(run, "run", sc.settings);
  run.finish();

  TableReader gm(file, root, "ground_motion");
  read_ground_motion_components(gm, file, base, "ground_motion", sc.ground_motion);
  read_run_settings(gm, "ground_motion", sc.settings);
  gm.boolean("baseline_correction", sc.ground_motion.baseline_correction);
  gm.finish();

  TableReader monitor(file, root, "monitor");
  monitor.integers("blocks", sc.monitor_blocks);
  monitor.finish();

  TableReader ensemble(file, root, "ensemble");
  EnsembleSpec& e = sc.ensemble;
  ensemble.integer_in("members", e.members, 0, 100000);
  int seed = static_cast<int>(e.seed);
  ensemble.integer_at_least("seed", seed, 0);
  e.seed = seed;
  ensemble.number_in("position_tolerance_m", e.position_tolerance_m, 0.0, 0.05);
  ensemble.range("friction_angle_deg", e.friction_angle_deg, 1.0, 60.0);
  ensemble.range("amplitude", e.amplitude, 0.0, 10.0);
  ensemble.finish();
  return sc;
}

}  // namespace ishibashi
