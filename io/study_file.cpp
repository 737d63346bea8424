#include "io/study_file.h"

#include "io/toml_reader.h"

namespace ishibashi {
namespace {

// The keys that both [study] and [quick] may set.
void read_common(TableReader& t, const std::filesystem::path& file, StudyFile& s) {
  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
  std::vector<std::filesystem::path> models, scenarios;
  t.paths_of_distinct_stems("models", base, models);
  t.paths_of_distinct_stems("scenarios", base, scenarios);
  if (!models.empty()) s.models = models;
  if (!scenarios.empty()) s.scenarios = scenarios;
  t.non_negative_numbers("snapshot_times_s", s.snapshot_times_s);
  t.number("duration_s", s.duration_s);  // < 0 (the default): each scenario's own, as study files say
  t.integer_at_least("members", s.members, 0);
}

// [reference]: every key names a model (frequencies_hz) or a scenario (says) of the study.
void read_reference(const std::filesystem::path& file, const toml::table& root, StudyFile& s) {
  TableReader reference(file, root, "reference");
  const toml::table* frequencies = reference.subtable("frequencies_hz");
  const toml::table* says = reference.subtable("says");
  const toml::table* outcome = reference.subtable("outcome");
  reference.finish();
  auto listed = [](const std::vector<std::filesystem::path>& files, const std::string& stem) {
    for (const auto& f : files)
      if (f.stem() == stem) return true;
    return false;
  };
  TableReader frequency_reader(file, frequencies, "reference.frequencies_hz");
  if (frequencies)
    for (const auto& [key, node] : *frequencies) {
      const std::string stem(key.str());
      if (!listed(s.models, stem)) frequency_reader.fail(node, "'" + stem + "' is no model file of [study] models");
      const toml::array* a = node.as_array();
      if (!a || a->size() != 3) frequency_reader.fail(node, "'" + stem + "' must be [x, y, z] in Hz");
      std::array<double, 3> hz{};
      for (int axis = 0; axis < 3; ++axis) {
        const auto v = (*a)[axis].value<double>();
        if (!v || !(*v > 0 && std::isfinite(*v))) frequency_reader.fail(node, "'" + stem + "' must hold three frequencies > 0, in Hz");
        hz[axis] = *v;
      }
      s.reference_frequencies_hz[stem] = hz;
    }
  TableReader says_reader(file, says, "reference.says");
  if (says)
    for (const auto& [key, node] : *says) {
      const std::string stem(key.str());
      if (!listed(s.scenarios, stem)) says_reader.fail(node, "'" + stem + "' is no scenario file of [study] scenarios");
      const auto text = node.value<std::string>();
      if (!text) says_reader.fail(node, "'" + stem + "' must be a string: what the study says of that run");
      s.reference_says[stem] = *text;
    }
  TableReader outcome_reader(file, outcome, "reference.outcome");
  if (outcome)
    for (const auto& [key, node] : *outcome) {
      const std::string stem(key.str());
      if (!listed(s.scenarios, stem)) outcome_reader.fail(node, "'" + stem + "' is no scenario file of [study] scenarios");
      const auto text = node.value<std::string>();
      if (!text || (*text != "collapse" && *text != "stands" && *text != "no_stone_falls"))
        outcome_reader.fail(node, "'" + stem + "' must be \"collapse\", \"stands\" or \"no_stone_falls\": the study's verdict");
      s.reference_outcome[stem] = *text;
    }
}

}  // namespace

StudyFile read_study(const std::filesystem::path& file, bool quick) {
  const toml::table root = parse_toml_file(file, kStudyFile);
  StudyFile s;
  s.file = file;
  TableReader study(file, root, "study");
  study.text("name", s.name);
  read_common(study, file, s);
  study.finish();
  TableReader frequencies(file, root, "frequencies");
  frequencies.integer_in("modes", s.modes, 1, 500);  // as modal --modes
  frequencies.non_negative("impulse_s", s.impulse_s);  // 0: no impulse responses
  frequencies.texts("joint_rules", s.joint_rules, kJointRuleNames);
  frequencies.finish();

  read_reference(file, root, s);  // against the whole study's models and scenarios

  TableReader short_version(file, root, "quick");
  StudyFile q = s;
  read_common(short_version, file, q);
  short_version.integer_in("modes", q.modes, 1, 500);
  short_version.non_negative("impulse_s", q.impulse_s);
  short_version.finish();
  if (quick) s = q;

  if (s.name.empty()) s.name = file.stem().string();
  if (s.models.empty() && s.scenarios.empty())
    throw InputError(file.string() + ": [study] lists no models and no scenarios (models = [\"...\"], scenarios = [\"...\"])");
  for (const auto& p : s.models)
    if (!std::filesystem::exists(p)) throw InputError(file.string() + ": model file " + p.string() + " does not exist");
  for (const auto& p : s.scenarios)
    if (!std::filesystem::exists(p)) throw InputError(file.string() + ": scenario file " + p.string() + " does not exist");
  return s;
}

}  // namespace ishibashi
