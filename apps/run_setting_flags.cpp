#include "apps/run_setting_flags.h"

#include <cstring>
#include <sstream>
#include <string>

namespace ishibashi {

CLI::Validator number_in(double min, double max, bool open_min) {
  std::ostringstream range, interval;  // for the message, and for --help: (0, 0.5], [0, inf)
  range << (open_min ? "> " : ">= ") << min;
  if (!std::isinf(max)) range << " and <= " << max;
  interval << (open_min ? "(" : "[") << min << ", " << max << (std::isinf(max) ? ")" : "]");
  return CLI::Validator(
      [min, max, open_min, range = range.str()](std::string& text) {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return text + " is not a number";
        const bool above = open_min ? value > min : value >= min;
        return above && value <= max ? std::string() : text + " must be " + range;
      },
      interval.str());
}

std::vector<CLI::Option*> add_run_setting_flags(CLI::App* cmd, RunOverrides& overrides,
                                                std::initializer_list<const char*> keys) {
  std::vector<CLI::Option*> added;
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    bool wanted = keys.size() == 0;
    for (const char* key : keys) wanted = wanted || std::strcmp(key, info.key) == 0;
    if (!wanted || !info.flag) return;
    using T = std::decay_t<decltype(overrides.values.*member)>;
    const std::string help = std::string(info.help) + ", replacing the scenario's " + info.key;
    if constexpr (std::is_enum_v<T>) {
      const auto& names = choice_names(T{});
      CLI::Option* option = cmd->add_option_function<std::string>(
          info.flag, [&overrides, member](const std::string& name) { overrides.set(member, static_cast<T>(choice_index<T>(name))); },
          help);
      option->check(CLI::IsMember(std::vector<std::string>(names.begin(), names.end())));
      added.push_back(option);
    } else {
      CLI::Option* option = cmd->add_option_function<T>(
          info.flag, [&overrides, member](const T& value) { overrides.set(member, value); }, help);
      option->check(number_in(info.min, info.max, info.open_min));  // the range the scenario file has
      added.push_back(option);
    }
  });
  return added;
}

}  // namespace ishibashi
