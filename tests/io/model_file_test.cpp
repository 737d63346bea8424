// Model files: presets read, and bad files name the file, line and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <toml++/toml.h>

#include "io/model_file.h"
#include "io/scenario_file.h"
#include "io/study_file.h"
#include "io/sweep_file.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string error_of(const std::string& text) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_model_test.toml";
  std::ofstream(file) << text;
  try {
    read_model_file(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// Every input file shipped with the program reads: models/ as model files, scenarios/ as
// scenario, sweep or study files (by their tables), with each scenario a sweep names.
TEST(ShippedFiles, EveryModelScenarioSweepAndStudyFileReads) {
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  int models = 0, scenarios = 0, sweeps = 0, studies = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root / "models"))
    if (entry.path().extension() == ".toml") {
      EXPECT_NO_THROW(read_model_file(entry.path())) << entry.path();
      ++models;
    }
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root / "scenarios")) {
    const std::filesystem::path& file = entry.path();
    if (file.extension() != ".toml") continue;
    const toml::table tables = toml::parse_file(file.string());
    try {
      if (tables.contains("sweep")) {
        for (const auto& scenario : read_sweep(file).scenarios) read_scenario(scenario);
        ++sweeps;
      } else if (tables.contains("study")) {
        read_study(file, false);
        if (tables.contains("quick")) read_study(file, true);
        ++studies;
      } else {
        read_scenario(file);
        ++scenarios;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GE(models, 9);
  EXPECT_GE(scenarios, 17);
  EXPECT_GE(sweeps, 4);
  EXPECT_GE(studies, 2);
}

TEST(ModelFile, PresetReads) {
  const ModelFile m = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / "nishida_f.toml");
  EXPECT_EQ(m.name, "Nishida F");
  EXPECT_EQ(m.bridge.spans, 2);
  EXPECT_DOUBLE_EQ(m.bridge.length_m, 36.0);
  EXPECT_DOUBLE_EQ(m.bridge.ring.span_m, 11.36);
  EXPECT_EQ(m.bridge.stone.name, "stone");
}

TEST(ModelFile, UnknownKeyNamesFileLineAndKey) {
  const std::string e = error_of("[ring]\nspan_m = 10.0\nrisee_m = 3.0\n");
  EXPECT_THAT(e, HasSubstr("ishibashi_model_test.toml:3"));
  EXPECT_THAT(e, HasSubstr("unknown key 'risee_m' in [ring]"));
}

TEST(ModelFile, WrongTypeAndBadChoiceAreErrors) {
  EXPECT_THAT(error_of("[bridge]\n\nfill_height_m = \"high\"\n"), HasSubstr(":3: 'fill_height_m' must be a number"));
  EXPECT_THAT(error_of("[bridge]\nbackfill = \"gravel\"\n"), HasSubstr("allowed: \"stone\", \"soil\""));
  EXPECT_THAT(error_of("[bridge]\nfixed_bottom_course = 1\n"), HasSubstr(":2: 'fixed_bottom_course' must be true or false"));
  EXPECT_THAT(error_of("[brigde]\n"), HasSubstr("unknown table or key 'brigde'"));
  // A scenario given where a model file goes: its table says which kind of file it is.
  EXPECT_THAT(error_of("[model]\nfile = \"a.toml\"\n[run]\nduration_s = 1\n"),
              HasSubstr("[run] belongs in a scenario file (scenarios/): is this the file the command takes?"));
  EXPECT_THAT(error_of("[brigde]\n"), Not(HasSubstr("belongs in")));
  EXPECT_THAT(error_of("[ring\n"), HasSubstr("ishibashi_model_test.toml:1"));
}

// A mesh given where a model or scenario file goes says how meshes come in, where TOML's
// parser said "expected '='" at its first line.
TEST(ModelFile, AMeshWhereATomlFileGoesSaysHowToImportIt) {
  const auto mesh = std::filesystem::temp_directory_path() / "ishibashi_stones.OFF";
  std::ofstream(mesh) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  try {
    read_model_file(mesh);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("ishibashi_stones.OFF: a mesh given where a model file (models/) goes, a TOML file"));
    EXPECT_THAT(e.what(), HasSubstr("[import] files = [\"ishibashi_stones.OFF\"]"));
  }
}

// mortar_parts: names of parts, at least one; anything else named at its line.
TEST(ModelFile, MortarPartsAreNamedPartsAndABadOneIsRefusedAtItsLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_model_test.toml";
  std::ofstream(file) << "[bridge]\nmortar_parts = [\"ring\", \"side_wall\"]\n";
  EXPECT_EQ(read_model_file(file).bridge.mortar_parts, (std::vector<Part>{Part::ring, Part::side_wall}));
  EXPECT_THAT(error_of("[bridge]\nmortar_parts = []\n"),
              HasSubstr(":2: 'mortar_parts' must be an array of one or more of \"ring\", \"wall\", \"fill\", \"side_wall\", \"ground\""));
  EXPECT_THAT(error_of("[bridge]\nmortar_parts = [\"ring\", \"spandrel\"]\n"), HasSubstr(":2: 'mortar_parts' may only hold \"ring\""));
  EXPECT_THAT(error_of("[bridge]\nmortar_parts = \"ring\"\n"), HasSubstr(":2: 'mortar_parts' must be an array"));
}

// [[tie]]: two anchor points and a diameter, steel's modulus and yield stress unless given;
// a missing or malformed entry named at its line.
TEST(ModelFile, TiesAreReadAndABadOneIsRefusedAtItsLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_model_test.toml";
  std::ofstream(file) << "[[tie]]\nfrom = [0, -1.5, 5]\nto = [0, 1.5, 5]\ndiameter_m = 0.03\n\n"
                      << "[[tie]]\nfrom = [1, -1.5, 5]\nto = [1, 1.5, 5.5]\ndiameter_m = 0.02\nyield_pa = 2e8\nyoung_pa = 1.9e11\n"
                      << "pretension_n = 2e4\n";
  const ModelFile m = read_model_file(file);
  ASSERT_EQ(m.ties.size(), 2u);
  EXPECT_EQ(m.ties[0].from, Vec3(0, -1.5, 5));
  EXPECT_EQ(m.ties[1].to, Vec3(1, 1.5, 5.5));
  EXPECT_EQ(m.ties[0].young_pa, 2.0e11);
  EXPECT_EQ(m.ties[0].yield_pa, 2.35e8);
  EXPECT_EQ(m.ties[1].yield_pa, 2e8);
  EXPECT_EQ(m.ties[1].line, 6);
  EXPECT_NEAR(m.ties[0].area_m2(), 7.0686e-4, 1e-8);
  EXPECT_EQ(m.ties[0].pretension_n, 0.0);
  EXPECT_EQ(m.ties[1].pretension_n, 2e4);
  EXPECT_EQ(ties_description(m), "2 tie rods, d = 20-30 mm, f_y = 200-235 MPa, yield force 62.8-166 kN, pretension 0-20 kN");
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0, 0]\ndiameter_m = 0.03\n"), HasSubstr(":1: [[tie]] needs from = [x, y, z]"));
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0, 0]\ndiameter_m = 0.03\n"), HasSubstr("'to' is missing"));
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0]\nto = [0, 1, 0]\ndiameter_m = 0.03\n"),
              HasSubstr(":2: 'from' must be a point [x, y, z] of three numbers, m"));
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0, 0]\nto = [0, 1, 0]\ndiameter_m = -0.03\n"), HasSubstr(":4: 'diameter_m' is -0.03"));
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0, 0]\nto = [0, 1, 0]\ndiameter_m = 0.03\nprestress = 5\n"),
              HasSubstr(":5: unknown key 'prestress' in [tie]"));
  EXPECT_THAT(error_of("[[tie]]\nfrom = [0, 0, 0]\nto = [0, 1, 0]\ndiameter_m = 0.03\npretension_n = -5\n"),
              HasSubstr(":5: 'pretension_n' is -5; it must be >= 0"));
  EXPECT_THAT(error_of("[tie]\nfrom = [0, 0, 0]\n"), HasSubstr(":1: 'tie' must be [[tie]] tables"));
}

// [[tie_row]]: where the rods cross (x_m, any sign), their height and diameter; the inset
// and the steel's properties have defaults; each rod carries the row's line.
TEST(ModelFile, TieRowsAreReadAndABadOneIsRefusedAtItsLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_model_test.toml";
  std::ofstream(file) << "[[tie]]\nfrom = [0, -1.5, 5]\nto = [0, 1.5, 5]\ndiameter_m = 0.03\n\n"
                      << "[[tie_row]]\nx_m = [-3, 0, 4.5]\nz_m = 5.44\ndiameter_m = 0.02\n\n"
                      << "[[tie_row]]\nx_m = [1]\nz_m = -1\ndiameter_m = 0.03\ninset_m = 0.1\npretension_n = 1e4\n";
  const ModelFile m = read_model_file(file);
  ASSERT_EQ(m.tie_rows.size(), 2u);
  EXPECT_EQ(m.tie_rows[0].x_m, (std::vector<double>{-3, 0, 4.5}));
  EXPECT_EQ(m.tie_rows[0].z_m, 5.44);
  EXPECT_EQ(m.tie_rows[0].inset_m, 0.05);
  EXPECT_EQ(m.tie_rows[0].rod.diameter_m, 0.02);
  EXPECT_EQ(m.tie_rows[0].rod.yield_pa, 2.35e8);
  EXPECT_EQ(m.tie_rows[0].rod.line, 6);
  EXPECT_EQ(m.tie_rows[1].z_m, -1.0);
  EXPECT_EQ(m.tie_rows[1].inset_m, 0.1);
  EXPECT_EQ(m.tie_rows[1].rod.pretension_n, 1e4);
  EXPECT_EQ(ties_description(m), "5 tie rods, d = 20-30 mm, f_y = 235 MPa, yield force 73.8-166 kN, pretension 0-10 kN");
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = [0]\ndiameter_m = 0.03\n"), HasSubstr(":1: [[tie_row]] needs x_m"));
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = [0]\ndiameter_m = 0.03\n"), HasSubstr("'z_m' is missing"));
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = []\nz_m = 5\ndiameter_m = 0.03\n"), HasSubstr(":1: [[tie_row]] x_m is empty"));
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = [0, \"a\"]\nz_m = 5\ndiameter_m = 0.03\n"), HasSubstr(":2: 'x_m' must hold finite numbers"));
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = [0]\nz_m = 5\ndiameter_m = 0.03\ninset_m = 0\n"), HasSubstr(":5: 'inset_m' is 0; it must be > 0"));
  EXPECT_THAT(error_of("[[tie_row]]\nx_m = [0]\nz_m = 5\ndiameter_m = 0.03\ny_m = 1\n"), HasSubstr(":5: unknown key 'y_m' in [tie_row]"));
  EXPECT_THAT(error_of("[tie_row]\nx_m = [0]\n"), HasSubstr(":1: 'tie_row' must be [[tie_row]] tables"));
}

TEST(ModelFile, NumbersOutOfRangeNameTheirLine) {
  EXPECT_THAT(error_of("[ring]\nrise_m = 3.0\nspan_m = -3.0\n"), HasSubstr(":3: 'span_m' is -3; it must be > 0"));
  EXPECT_THAT(error_of("[ring]\nvoussoirs = 0\n"), HasSubstr(":2: 'voussoirs' is 0; it must be at least 1"));
  EXPECT_THAT(error_of("[stone]\n\npoisson = 0.7\n"), HasSubstr(":3: 'poisson' is 0.7; it must be >= 0 and <= 0.4999"));
  EXPECT_THAT(error_of("[bridge]\nmortar_pa = -1\n"), HasSubstr(":2: 'mortar_pa' is -1; it must be >= 0"));
  EXPECT_THAT(error_of("[bridge]\n\nground_margin_m = -2\n"), HasSubstr(":3: 'ground_margin_m' is -2; it must be >= 0"));
  // TOML's nan and inf pass no range check either (a NaN would fail none of them silently).
  EXPECT_THAT(error_of("[bridge]\nmortar_pa = nan\n"), HasSubstr(":2: 'mortar_pa' is nan; it must be a finite number"));
  EXPECT_THAT(error_of("[ring]\n\nspan_m = inf\n"), HasSubstr(":3: 'span_m' is inf; it must be a finite number"));
  EXPECT_THAT(error_of("[bridge]\nmortar_pa = 2e5\nmortar_tension_fracture_j_m2 = 12\n"),
              HasSubstr("[bridge] mortar_tension_fracture_j_m2 and mortar_shear_fracture_j_m2 must both be > 0"));
}

}  // namespace
}  // namespace ishibashi

namespace ishibashi {
namespace {

// A scenario's dashpot choice: "capped" read, anything else refused at its line.
// A scenario of model A whose [run] table holds `run_line` on its line 5.
void write_scenario(const std::filesystem::path& file, const std::string& run_line) {
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  std::ofstream(file) << "[model]\nfile = \"" << (root / "models/nishida_a.toml").string() << "\"\n[run]\nduration_s = 1\n"
                      << run_line << "\n[ground_motion]\nx = { file = \""
                      << (root / "data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM090.AT2").string() << "\" }\n";
}

TEST(ScenarioFile, DampingIsStudyCappedOrImplicitAndABadChoiceNamesItsLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_scenario_damping.toml";
  auto write = [&](const std::string& damping) { write_scenario(file, damping); };
  write("");
  EXPECT_EQ(read_scenario(file).settings.damping, Damping::study);
  write("damping = \"capped\"");
  EXPECT_EQ(read_scenario(file).settings.damping, Damping::capped);
  write("damping = \"implicit\"");
  EXPECT_EQ(read_scenario(file).settings.damping, Damping::implicit);
  write("damping = \"none\"");
  try {
    read_scenario(file);
    ADD_FAILURE() << "damping = \"none\" was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("ishibashi_scenario_damping.toml:5"));
    EXPECT_THAT(e.what(), HasSubstr("allowed: \"study\", \"capped\""));
  }
}

// A component's column and header of a file of several components, read from the scenario;
// refused for the formats that say where their samples are, and a column from 1.
TEST(ScenarioFile, ColumnSettingsAreForColumnFiles) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_scenario_columns.toml";
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  auto write = [&](const std::string& component) {
    std::ofstream(file) << "[model]\nfile = \"" << (root / "models/nishida_a.toml").string()
                        << "\"\n[run]\nduration_s = 1\n[ground_motion]\nz = " << component << "\n";
  };
  write("{ file = \"three.csv\", format = \"columns\", unit = \"gal\", column = 4, header_lines = 2 }");
  const ComponentSpec z = *read_scenario(file).ground_motion.component[2];
  EXPECT_EQ(z.layout.column, 4);
  EXPECT_EQ(z.layout.header_lines, 2);
  EXPECT_EQ(z.layout.dt_s, 0.0);
  for (const auto& [component, message] :
       {std::pair<std::string, std::string>{"{ file = \"a.AT2\", column = 2 }", "column and header_lines are for format = \"columns\""},
        {"{ file = \"a.AT2\", unit = \"gal\" }", "z: unit, dt_s, column and header_lines are for format = \"columns\" (at2 files"},
        {"{ file = \"a.txt\", format = \"knet\", dt_s = 0.01 }", "z: unit, dt_s, column and header_lines are for format"},
        {"{ file = \"a.csv\", format = \"columns\", column = 0 }", "'column' is 0; it must be at least 1"},
        {"{ file = \"a.csv\", format = \"columns\", header_lines = -1 }", "'header_lines' is -1"},
        {"{ file = \"a.csv\", format = \"columns\", dt_s = -0.01 }", "'dt_s' is -0.01; it must be >= 0"}}) {
    write(component);
    try {
      read_scenario(file);
      ADD_FAILURE() << component << ": accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message)) << component;
    }
  }
}

// A scenario's own numbers are finite: its mortar_pa = nan once meant "as the model file
// says" (a dry bridge run without a word), and nan in [run] or [ground_motion] is refused
// at its line as well.
TEST(ScenarioFile, NanOrInfinityIsRefusedAtItsLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_scenario_nan.toml";
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  const std::string record = (root / "data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM090.AT2").string();
  for (const auto& [text, message] :
       {std::pair<std::string, std::string>{"[model]\nfile = \"" + (root / "models/nishida_a.toml").string() +
                                                "\"\nmortar_pa = nan\n[run]\nduration_s = 1\n[ground_motion]\nx = { file = \"" +
                                                record + "\" }\n",
                                            ":3: 'mortar_pa' is nan; it must be a finite number"}}) {
    std::ofstream(file) << text;
    try {
      read_scenario(file);
      ADD_FAILURE() << message << ": accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  }
  for (const auto& [line, message] : {std::pair<std::string, std::string>{"settle_kinetic_j = nan", ":5: 'settle_kinetic_j' is nan"},
                                      {"output_interval_s = inf", ":5: 'output_interval_s' is inf"},
                                      {"dt_s = -inf", ":5: 'dt_s' is -inf"}}) {
    write_scenario(file, line);
    try {
      read_scenario(file);
      ADD_FAILURE() << line << " was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message + "; it must be a finite number"));
    }
  }
}

// [model]'s mortar overrides: absent keeps the model file's value, a value given replaces it,
// and a negative one is refused at its line (it once read as "absent": a user's typo of -5
// ran the model file's mortar without a word).
TEST(ScenarioFile, MortarOverridesReplaceTheModelsAndANegativeOneIsRefused) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_scenario_mortar.toml";
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  const std::string record = (root / "data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM090.AT2").string();
  auto write = [&](const std::string& model_line) {
    std::ofstream(file) << "[model]\nfile = \"" << (root / "models/nishida_a.toml").string() << "\"\n"
                        << model_line << "\n[run]\nduration_s = 1\n[ground_motion]\nx = { file = \"" << record << "\" }\n";
  };
  const double model_value = read_model_file(root / "models/nishida_a.toml").bridge.mortar_pa;
  write("");
  EXPECT_EQ(read_scenario(file).model.bridge.mortar_pa, model_value);
  write("mortar_pa = 250000.0");
  EXPECT_EQ(read_scenario(file).model.bridge.mortar_pa, 250000.0);
  EXPECT_TRUE(read_scenario(file).model.bridge.mortar_parts.empty());  // the model file's: every stone part
  write("mortar_parts = [\"ring\"]");
  EXPECT_EQ(read_scenario(file).model.bridge.mortar_parts, std::vector<Part>{Part::ring});
  for (const std::string key : {"mortar_pa", "mortar_tension_fracture_j_m2", "mortar_shear_fracture_j_m2"}) {
    write(key + " = -5.0");
    try {
      read_scenario(file);
      ADD_FAILURE() << key << " = -5 was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("ishibashi_scenario_mortar.toml:3: '" + key + "' is -5; it must be >= 0"));
    }
  }
}

// A scenario's joint rule and subdivision: read, and anything out of range refused at its line.
TEST(ScenarioFile, JointRuleAndSubdivisionAreCheckedAtTheirLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_scenario_joint_rule.toml";
  auto write = [&](const std::string& run) { write_scenario(file, run); };
  write("");
  EXPECT_EQ(read_scenario(file).settings.joint_rule, JointRule::corners);
  write("joint_rule = \"moments\"");
  EXPECT_EQ(read_scenario(file).settings.joint_rule, JointRule::moments);
  for (const auto& [line, message] : {std::pair<std::string, std::string>{"joint_rule = \"gauss\"", "allowed: \"corners\", \"moments\""},
                                      {"subdivision = 17", "'subdivision' is 17; it must be at least 1 and at most 16"}}) {
    write(line);
    try {
      read_scenario(file);
      ADD_FAILURE() << line << " was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("ishibashi_scenario_joint_rule.toml:5"));
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  }
}

// A shipped scenario copied into a folder of its own: its ../models and ../data paths now
// lead nowhere. The model is refused as the scenario is read, the record as it is loaded,
// each with the path it was looked for at; copied with both folders, it reads.
TEST(ScenarioFile, ACopyWithoutItsModelsAndDataSaysWhereTheyWereLookedFor) {
  const auto root = std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  const auto copy = std::filesystem::temp_directory_path() / "copied" / "scenarios";
  std::filesystem::create_directories(copy);
  std::filesystem::copy_file(root / "scenarios/nishida_a_kobe_dry.toml", copy / "a.toml",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string where = (copy.parent_path() / "models/nishida_a.toml").string();
  try {
    read_scenario(copy / "a.toml");
    ADD_FAILURE() << "a scenario whose model file is missing was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr((copy / "a.toml").string() + ": [model] file = \"../models/nishida_a.toml\" is " + where +
                                    ", which does not exist"));
  }
  std::filesystem::copy(root / "models", copy.parent_path() / "models", std::filesystem::copy_options::recursive);
  const Scenario sc = read_scenario(copy / "a.toml");
  try {
    ground_motion_peaks(sc.ground_motion);
    ADD_FAILURE() << "a missing record was loaded";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr((copy.parent_path() / "data/ground_motions/kobe_1995_jma").string()));
    EXPECT_THAT(e.what(), HasSubstr("no such ground-motion file"));
  }
  std::filesystem::copy(root / "data", copy.parent_path() / "data", std::filesystem::copy_options::recursive);
  EXPECT_GT(horizontal_pga_m_s2(read_scenario(copy / "a.toml").ground_motion), 0.0);
}

}  // namespace
}  // namespace ishibashi
