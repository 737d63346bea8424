// The run settings' one list (io/run_settings.h): every setting it declares is read from
// its scenario table, checked against its range at its line, and overridden only when given.
#include "io/run_settings.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "geometry/input_error.h"
#include "io/scenario_file.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

// A value of each setting other than its default, as TOML text and as the value.
struct Other {
  std::string toml;
  RunSettings expected;
};

Other other_values() {
  Other o;
  std::map<std::string, std::ostringstream> tables;
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    auto& value = o.expected.*member;
    using T = std::decay_t<decltype(value)>;
    std::ostringstream& t = tables[info.table];
    if constexpr (std::is_enum_v<T>) {
      value = static_cast<T>((static_cast<int>(value) + 1) % choice_names(value).size());
      t << info.key << " = \"" << choice_names(value)[static_cast<int>(value)] << "\"\n";
    } else if constexpr (std::is_same_v<T, int>) {
      value += 1;
      t << info.key << " = " << value << "\n";
    } else {
      value += 0.25;
      t << info.key << " = " << value << "\n";
    }
  });
  const std::string root = ISHIBASHI_SOURCE_DIR;
  o.toml = "[model]\nfile = \"" + root + "/models/nishida_a.toml\"\n" + tables["model"].str() + "[run]\n" + tables["run"].str() +
           "[ground_motion]\nx = { file = \"" + root + "/data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM090.AT2\" }\n" +
           tables["ground_motion"].str();
  EXPECT_EQ(tables.size(), 3u) << "a setting in a table the scenario file does not have";
  return o;
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto file = std::filesystem::temp_directory_path() / name;
  std::ofstream(file) << text;
  return file;
}

TEST(RunSettings, EveryDeclaredSettingIsReadFromItsTable) {
  const Other o = other_values();
  const Scenario sc = read_scenario(write("ishibashi_every_setting.toml", o.toml));
  int count = 0;
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    EXPECT_EQ(sc.settings.*member, o.expected.*member) << info.key;
    EXPECT_NE(sc.settings.*member, RunSettings{}.*member) << info.key << " kept its default";
    ++count;
  });
  EXPECT_GE(count, 12);
  EXPECT_EQ(sc.motion().start_s, o.expected.start_s);  // the window the run prepares
  EXPECT_EQ(sc.motion().duration_s, o.expected.duration_s);
}

// Each number below its range is refused with the file, its line and the key.
TEST(RunSettings, ANumberOutOfItsRangeIsRefusedAtItsLine) {
  const std::string text = other_values().toml;
  for_each_run_setting([&](const SettingInfo& info, auto member) {
    using T = std::decay_t<decltype(RunSettings{}.*member)>;
    if constexpr (!std::is_enum_v<T>) {
      const std::string key = std::string(info.key) + " = ";
      const std::size_t at = text.find("\n" + key) + 1;
      const int line = static_cast<int>(std::count(text.begin(), text.begin() + at, '\n')) + 1;
      std::string bad = text;
      bad.replace(at, text.find('\n', at) - at, key + (info.open_min ? "0" : std::to_string(static_cast<T>(info.min) - 1)));
      try {
        read_scenario(write("ishibashi_bad_setting.toml", bad));
        ADD_FAILURE() << info.key << " below its range was accepted";
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("ishibashi_bad_setting.toml:" + std::to_string(line) + ": '" + info.key + "'"));
      }
    }
  });
}

TEST(RunSettings, OverridesReplaceOnlyWhatWasGiven) {
  RunSettings settings;
  settings.dt_s = 1e-5;
  RunOverrides overrides;
  overrides.values.duration_s = 7;  // not given: ignored
  overrides.set(&RunSettings::joint_rule, JointRule::moments).set(&RunSettings::threads, 3);
  apply_overrides(settings, overrides);
  EXPECT_EQ(settings.joint_rule, JointRule::moments);
  EXPECT_EQ(settings.threads, 3);
  EXPECT_EQ(settings.dt_s, 1e-5);
  EXPECT_EQ(settings.duration_s, RunSettings{}.duration_s);
  EXPECT_EQ(overrides.given, (std::set<std::string>{"joint_rule", "threads"}));
}

TEST(RunSettings, ModelOptionsCarryTheJointAndDashpotSettings) {
  RunSettings s;
  s.subdivision = 3, s.joint_rule = JointRule::moments, s.shear_spring = ShearSpring::normal, s.damping = Damping::implicit;
  s.mortar_bonds = MortarBonds::initial;
  s.solve_tolerance = 1e-2;
  const ModelOptions o = model_options(s);
  EXPECT_EQ(o.subdivision, 3);
  EXPECT_EQ(o.joint_rule, JointRule::moments);
  EXPECT_EQ(o.shear_spring, ShearSpring::normal);
  EXPECT_EQ(o.damping, Damping::implicit);
  EXPECT_EQ(o.damping_solve_tolerance, 1e-2);
  EXPECT_FALSE(o.bonds_when_settled);
  EXPECT_TRUE(model_options(RunSettings{}).bonds_when_settled);
}

TEST(RunSettings, EachChoiceParsesFromItsNameAndABadNameListsTheChoices) {
  for (JointRule r : {JointRule::corners, JointRule::moments}) EXPECT_EQ(parse_joint_rule(joint_rule_name(r)), r);
  for (ShearSpring s : {ShearSpring::shear_modulus, ShearSpring::normal}) EXPECT_EQ(parse_shear_spring(shear_spring_name(s)), s);
  for (Damping d : {Damping::study, Damping::capped, Damping::implicit}) EXPECT_EQ(parse_damping(damping_name(d)), d);
  try {
    parse_joint_rule("gauss");
    ADD_FAILURE() << "\"gauss\" was accepted";
  } catch (const ModelError& e) {
    EXPECT_THAT(e.what(), HasSubstr("joint_rule is \"gauss\"; it must be \"corners\" or \"moments\""));
  }
}

}  // namespace
}  // namespace ishibashi
