#include "io/sweep_file.h"

#include <cstdio>
#include <set>

#include "io/ground_motion.h"
#include "io/scenario_file.h"
#include "io/toml_reader.h"

namespace ishibashi {
namespace {

// Record and scenario names name run folders and are fields of sweep.csv.
bool is_folder_name(const std::string& name) {
  return !name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") ==
                              std::string::npos;
}

}  // namespace

std::string level_label(double level) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", level);
  return text;
}

SweepFile read_sweep(const std::filesystem::path& file) {
  const toml::table root = parse_toml_file(file, kSweepFile);
  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
  SweepFile s;
  s.file = file;

  TableReader sweep(file, root, "sweep");
  std::string scenario;
  sweep.text("scenario", scenario);
  sweep.paths_of_distinct_stems("scenarios", base, s.scenarios);
  sweep.non_negative("duration_s", s.duration_s);
  sweep.integer_at_least("members", s.members, 1);
  std::vector<double> pga, scale;
  sweep.non_negative_numbers("pga_g", pga);
  sweep.non_negative_numbers("scale", scale);
  sweep.finish();
  if (scenario.empty() == s.scenarios.empty())
    throw InputError(file.string() + ": [sweep] needs either scenario = \"...\" (the model and how to run it) or scenarios = "
                     "[\"...\", ...] (variants to compare on the same records)");
  if (!scenario.empty()) s.scenarios.push_back(base / scenario);
  for (const std::filesystem::path& sc : s.scenarios) {
    if (!std::filesystem::exists(sc)) throw InputError(file.string() + ": scenario " + sc.string() + " does not exist");
    if (!is_folder_name(sc.stem().string()))
      throw InputError(file.string() + ": scenario file name " + sc.filename().string() +
                       " must be letters, digits, '_', '-' or '.' before .toml (it names folders and rows of sweep.csv)");
    if (read_scenario(sc).settings.stop_at != StopAt::end)  // a run stopped before its failure would count as a survival
      throw InputError(file.string() + ": scenario " + sc.filename().string() + " ends its runs at their collapse ([run] "
                       "stop_at = \"collapse\"); a sweep ends them at its own failure criteria: [failure] stop_at_failure = true");
  }
  if (pga.empty() == scale.empty())
    throw InputError(file.string() + ": [sweep] needs either pga_g = [...] (target PGAs, g) or scale = [...] (factors)");
  s.scale_to_pga = !pga.empty();
  s.levels = s.scale_to_pga ? pga : scale;
  std::set<std::string> labels;
  for (double level : s.levels) {
    if (!(level > 0)) throw InputError(file.string() + ": [sweep] intensity levels must be > 0");
    if (!labels.insert(level_label(level)).second)
      throw InputError(file.string() + ": [sweep] lists the level " + level_label(level) +
                       " twice (a level names its runs' folders; for more runs per level, use members = N)");
  }

  TableReader failure(file, root, "failure");
  failure.boolean("collapse", s.failure.collapse);
  failure.positive("crown_drop_m", s.failure.crown_drop_m);
  failure.integer_at_least("fallen_stones", s.failure.fallen_stones, 1);
  failure.boolean("stop_at_failure", s.failure.stop_at_failure);
  failure.finish();
  if (!s.failure.collapse && s.failure.crown_drop_m < 0 && s.failure.fallen_stones < 0)
    throw InputError(file.string() + ": [failure] names no failure, so every run would count as a survival: keep collapse = "
                     "true or set crown_drop_m = ... or fallen_stones = ...");

  const toml::node* records = root.get("record");
  const toml::array* list = records ? records->as_array() : nullptr;
  if (!list || list->empty())
    throw InputError(file.string() + ": no [[record]] tables (each: name, start_s, x/y/z = { file, format })");
  std::set<std::string> names;
  for (const toml::node& node : *list) {
    const toml::table* table = node.as_table();
    if (!table) throw InputError(file.string() + ":" + std::to_string(node.source().begin.line) + ": [[record]] must be a table");
    TableReader record(file, table, "record");
    SweepRecord r;
    record.text("name", r.name);
    record.non_negative("start_s", r.motion.start_s);
    read_ground_motion_components(record, file, base, "record", r.motion);
    record.finish();
    const auto line = std::to_string(node.source().begin.line);
    if (!is_folder_name(r.name))
      throw InputError(file.string() + ":" + line + ": [[record]] name must be letters, digits, '_', '-' or '.' (it names folders)");
    if (!names.insert(r.name).second) throw InputError(file.string() + ":" + line + ": record name '" + r.name + "' is used twice");
    if (!r.motion.component[0] && !r.motion.component[1] && !r.motion.component[2])
      throw InputError(file.string() + ":" + line + ": record '" + r.name + "' has no component (x, y or z)");
    // Its files are read now, so that one that cannot be read, or a start past the record's
    // end, is refused at its [[record]] before any run, not by every run of the sweep.
    try {
      horizontal_pga_m_s2(r.motion);
    } catch (const InputError& e) {
      throw InputError(file.string() + ":" + line + ": record '" + r.name + "': " + e.what());
    }
    s.records.push_back(std::move(r));
  }
  return s;
}

}  // namespace ishibashi
