#include "apps/run_setting_flags.h"

#include <cstring>
#include <limits>
#include <string>

namespace ishibashi {

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
      if (info.open_min) option->check(CLI::PositiveNumber);
      else if (std::isinf(info.max) && info.min == 0) option->check(CLI::NonNegativeNumber);
      else option->check(CLI::Range(static_cast<T>(info.min), std::isinf(info.max) ? std::numeric_limits<T>::max() : static_cast<T>(info.max)));
      added.push_back(option);
    }
  });
  return added;
}

}  // namespace ishibashi
