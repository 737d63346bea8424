// Seismic-run scenes for the analysis tests: small models of boxes and stones written as
// files, shaken by a record of samples, run into a folder and read back.
#pragma once
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/run/seismic_run.h"
#include "command_line.h"
#include "io/scenario_file.h"

namespace ishibashi::test {

constexpr double kG = 9.80665;  // standard gravity, m/s^2

// A scene in `dir`: a model of 1 x 1 x 0.3 m stones of 2,000 kg/m^3 (600 kg each) and fixed
// boxes (`model_lines`: its [import] table; `stone_lines`: more of the stone's [stone] keys),
// shaken along `axis` by `record` (g, samples 1 ms apart); `run_lines` follow the scenario's
// [model] file line: its other keys, then [run].
inline Scenario scene(const std::filesystem::path& dir, const std::string& model_lines, const std::string& run_lines,
                       const std::vector<double>& record, const char* axis = "x", const std::string& stone_lines = "") {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "model.toml") << model_lines << "[stone]\ndensity_kg_m3 = 2000\n" << stone_lines;
  std::ofstream samples(dir / "record.txt");
  samples.precision(17);
  for (double a : record) samples << a << '\n';
  samples.close();
  std::ofstream(dir / "scene.toml") << "[model]\nfile = \"" << (dir / "model.toml").string() << "\"\n"
                                    << run_lines << "[ground_motion]\nbaseline_correction = false\n"
                                    << axis << " = { file = \"" << (dir / "record.txt").string()
                                    << "\", format = \"columns\", unit = \"g\", dt_s = 0.001 }\n";
  return read_scenario(dir / "scene.toml");
}

// The [import] table of a 1 x 1 x 0.3 m stone (block 0) from z = stone_z and a fixed
// 4 x 4 x 0.5 m slab under (or over) it from z = slab_z (m), their OFF files in `dir`.
inline std::string stone_and_slab(const std::filesystem::path& dir, double stone_z = 0.5, double slab_z = 0) {
  std::filesystem::create_directories(dir);
  box_off_file(dir / "stone.off", {1.5, 1.5, stone_z}, {1, 1, 0.3});
  box_off_file(dir / "slab.off", {0, 0, slab_z}, {4, 4, 0.5});
  return "[import]\nfiles = [\"" + (dir / "stone.off").string() + "\"]\nfixed_files = [\"" + (dir / "slab.off").string() + "\"]\n";
}

inline SeismicRunResult run_into(const std::filesystem::path& out, const Scenario& sc) {
  std::filesystem::remove_all(out);
  SeismicRunOptions options;
  options.out = out;
  return SeismicRun(sc, options).run();
}

// history.csv's rows as columns by name.
inline std::map<std::string, std::vector<std::string>> history(const std::filesystem::path& out) {
  std::ifstream in(out / "history.csv");
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream header(line); std::getline(header, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<std::string>> columns;
  while (std::getline(in, line)) {
    std::size_t k = 0;
    for (std::stringstream row(line); std::getline(row, cell, ',');) columns[names.at(k++)].push_back(cell);
  }
  return columns;
}

}  // namespace ishibashi::test
