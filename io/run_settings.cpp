#include "io/run_settings.h"

#include <climits>
#include <sstream>

#include "io/toml_reader.h"

namespace ishibashi {

ModelOptions model_options(const RunSettings& s) {
  ModelOptions options;
  options.subdivision = s.subdivision;
  options.joint_rule = s.joint_rule;
  options.shear_spring = s.shear_spring;
  options.damping = s.damping;
  options.damping_solve_tolerance = s.solve_tolerance;
  options.bonds_when_settled = s.mortar_bonds == MortarBonds::settled;
  return options;
}

void read_run_settings(TableReader& reader, const std::string& table, RunSettings& settings) {
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    if (table != info.table) return;
    auto& value = settings.*member;
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_enum_v<T>)
      reader.choice(info.key, value);
    else if constexpr (std::is_same_v<T, int>)
      reader.integer_in(info.key, value, static_cast<int>(info.min), std::isinf(info.max) ? INT_MAX : static_cast<int>(info.max));
    else
      reader.number_in(info.key, value, info.min, info.max, info.open_min);
  });
}

std::string settings_key_text(const RunSettings& settings) {
  std::ostringstream text;
  text.precision(17);
  for_each_run_setting([&](const SettingInfo& info, auto m) {
    if (std::string(info.key) != "threads") text << ' ' << info.key << '=' << setting_value(settings.*m);
  });
  return text.str();
}

void apply_overrides(RunSettings& settings, const RunOverrides& overrides) {
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    if (overrides.given.count(info.key)) settings.*member = overrides.values.*member;
  });
}

}  // namespace ishibashi
