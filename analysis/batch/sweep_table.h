// sweep.csv: its columns, its finished rows, and what is made from them at the end of a
// sweep: the IDA curves, a fragility curve per scenario, and each scenario against the
// first (sweep.h lists the files).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/batch/fragility.h"
#include "io/sweep_file.h"

namespace ishibashi {

// Which run, whether it failed, the run's result (run_result.h) and where it ran: wall_s
// and host, which differ from machine to machine, last. Ends with a newline.
const std::string& sweep_csv_header();
// Index of a column of the header; throws std::logic_error for a name it lacks.
std::size_t sweep_column(const std::string& name);
// A variant's name: its scenario file's stem.
std::string scenario_name(const SweepFile& sweep, int scenario);

// The complete rows of sweep.csv, each with its newline (a row cut short by a crash is dropped).
std::vector<std::string> finished_sweep_rows(const std::filesystem::path& file);
std::vector<std::string> row_fields(const std::string& row);

// A scenario's fragility over its rows of sweep.csv, and against the first scenario's.
struct ScenarioFragility {
  std::string scenario;
  FragilityFit fit;
  std::string reference;  // the first scenario (empty for the first itself)
  int cases = 0;          // (record, level, member) run with both
  int both_stand = 0, both_fail = 0, only_reference_fails = 0, only_scenario_fails = 0;
  FragilityComparison against_reference;
};

// Writes ida.csv, fragility_fit.csv, fragility.csv and (several scenarios) comparison.csv
// into `out` from the rows; returns each scenario's fit, in the sweep file's order.
std::vector<ScenarioFragility> write_sweep_curves(const SweepFile& sweep, const std::filesystem::path& out,
                                                  const std::vector<std::string>& rows);

}  // namespace ishibashi
