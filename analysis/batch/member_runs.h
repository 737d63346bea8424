// What ensembles (ensemble.h) and chaos probes (chaos_probe.h) share: running a member
// in its own folder so that an interrupted set of runs resumes, and the tables of the
// members' outcomes as probabilities with their sampling error.
#pragma once
#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/run/seismic_run.h"

namespace ishibashi {

// The 95 % Wilson score interval (z = 1.96) of a proportion: `hits` of `trials`, {lo, hi}.
std::array<double, 2> wilson_interval(int hits, int trials, double z = 1.959963984540054);

// {"median", "min", "max", "count"} of the values (null where there are none).
nlohmann::ordered_json value_spread(const std::vector<double>& values);

// A number as a stream writes it by default (6 significant digits): the tables' draws.
std::string number_text(double v);

// out/member_NNN
std::filesystem::path member_folder(const std::filesystem::path& out, int member);

enum class MemberStatus { current, ran, interrupted, failed };

// Runs a member in `folder`: kept when its outputs are stamped with `key`; continued from
// its checkpoint when the folder was started with `key`; else `start` makes a new run
// (the folder emptied and marked started with `key` first, so that `start` may put files
// in it). A finished run's checkpoint is removed and its outputs stamped with `key`,
// unless it stopped before its end without a stop request (a chaos probe's branch run:
// its checkpoint is the branch point). `event` gets a line for each change; a failure is
// one more line ("NAME: FAILED: why") and MemberStatus::failed.
using StartRun = std::function<std::unique_ptr<SeismicRun>(const SeismicRunOptions& options)>;
MemberStatus run_in_folder(const std::filesystem::path& folder, const std::string& key, const std::string& name,
                           SeismicRunOptions options, int threads, const StartRun& start,
                           const std::function<void(const std::string&)>& event);

// The same, a failure thrown to the caller (a sweep reports it in its own words). `started_as`:
// the scenario `start` runs where it is not the file as written (SeismicRun::resume);
// `result`, where given, gets the run's result when it ran.
MemberStatus run_in_folder_or_throw(const std::filesystem::path& folder, const std::string& key, const std::string& name,
                                    SeismicRunOptions options, int threads, const StartRun& start,
                                    const std::function<void(const std::string&)>& event,
                                    const Scenario* started_as = nullptr, SeismicRunResult* result = nullptr);

// Members' outcomes, each from its folder's summary.json and history.csv.
struct OutcomeTable {
  std::vector<std::string> draw_columns;  // leading columns of the CSV (the draws' names)
  struct Row {
    int member = 0;
    std::filesystem::path folder;
    std::vector<std::string> draws;  // (draw_columns)
  };
  std::vector<Row> rows;  // the finished members
};
struct OutcomeCounts {
  int finished = 0, collapses = 0, stones_fell = 0, ring_stones_fell = 0;
  // The member of the most common outcome (of the verdict most members share, collapse or
  // not, the one with the median number of fallen stones) and of the worst (the most fallen
  // stones, then the largest crown drop); -1: no member finished.
  int typical = -1, worst = -1;
  // How many members fail each way (the result's failure_mode), the most common first.
  std::vector<std::pair<std::string, int>> failure_modes;
};
// summary.json's result columns (run_result.h) as a CSV row's fields, without a newline.
std::string summary_csv_values(const nlohmann::json& summary);

// Writes `csv` (a row per member: member, its draws, summary.json's result columns,
// first_fall_s and stopped_early) and puts into `json` the probabilities of
// collapse, of any stone falling and of a ring stone falling, each with its Wilson interval,
// the median, least and largest fallen stones, first opening, first fall, crown drop and
// most ring hinges at once (members of a model with a ring), how
// many members fail each way ("failure_modes") and in how many members each stone fell
// ("fallen_blocks"); beside `csv`, fallen_share.vtu: the model's blocks (a member's first
// frame) with that share of the members as cell array fallen_share.
OutcomeCounts write_outcomes(const OutcomeTable& table, const std::filesystem::path& csv, nlohmann::ordered_json& json);

}  // namespace ishibashi
