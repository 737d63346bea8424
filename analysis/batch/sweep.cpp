#include "analysis/batch/sweep.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#include "analysis/batch/job_queue.h"
#include "analysis/batch/member_runs.h"
#include "analysis/batch/mpi_ranks.h"
#include "analysis/batch/sweep_table.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/folder_lock.h"
#include "geometry/input_error.h"
#include "io/scenario_file.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;

struct Case {
  int scenario, record, level, member;  // member: of the sweep's members (0 when it has none)
  std::string key;  // "scenario,record,level,member": the first four fields of its row
};

std::string host_name() {
  char name[256] = "";
  gethostname(name, sizeof name - 1);
  return name;
}

fs::path case_folder(const SweepFile& sweep, const Case& c, const fs::path& out) {
  const std::string member = sweep.members > 1 ? "_member_" + std::to_string(c.member) : "";
  return out / "runs" / scenario_name(sweep, c.scenario) /
         (sweep.records[c.record].name + "_" + level_label(sweep.levels[c.level]) + member);
}

// The inputs key of a case (job_queue.h): its scenario with its model file and records, the
// sweep's record (files, window), the level and how it scales, the duration, and the
// failure criteria its row applies.
std::string case_key(const SweepFile& sweep, const Case& c) {
  const SweepRecord& record = sweep.records[c.record];
  const FailureCriteria& f = sweep.failure;
  std::ostringstream in;
  in.precision(17);
  in << "sweep case " << scenario_fingerprint(sweep.scenarios[c.scenario]) << " level " << sweep.levels[c.level]
     << (sweep.scale_to_pga ? " pga" : " factor") << " duration " << sweep.duration_s << " start " << record.motion.start_s
     << " failure " << f.collapse << " " << f.crown_drop_m << " " << f.fallen_stones  // baseline: the scenario's
     << (f.stop_at_failure ? " stop" : "");
  if (sweep.members > 1) in << " member " << c.member << " of " << sweep.members;  // the draws: the scenario's [ensemble]
  for (const auto& component : record.motion.component)
    if (component)
      in << " " << fnv1a(file_bytes(component->file)) << " " << component->format << " " << static_cast<int>(component->unit)
         << " " << component->layout.dt_s << " " << component->layout.column << " " << component->layout.header_lines << " "
         << component->scale;
  return inputs_key(in.str());
}

bool has_failed(const FailureCriteria& f, const SeismicRunResult& r) {
  return (f.collapse && r.collapse) || (f.crown_drop_m >= 0 && r.largest_crown_drop_m > f.crown_drop_m) ||
         (f.fallen_stones >= 0 && r.fallen_stones >= f.fallen_stones);
}

// One run of the sweep, in its folder: it goes on from the checkpoint a killed or interrupted
// sweep left there for the same case (a case is hours of a large bridge, a cluster job's wall
// time may end any time), else starts; returns its row (with the newline). `event` gets its
// progress.
std::string run_case(const SweepFile& sweep, const Case& c, int threads, const fs::path& out, double checkpoint_wall_s,
                     const std::function<void(const std::string&)>& event) {
  const SweepRecord& record = sweep.records[c.record];
  const double level = sweep.levels[c.level];
  Scenario sc = read_scenario(sweep.scenarios[c.scenario]);
  RunOverrides overrides;
  overrides.set(&RunSettings::threads, threads).set(&RunSettings::start_s, record.motion.start_s);
  if (sweep.duration_s >= 0) overrides.set(&RunSettings::duration_s, sweep.duration_s);
  apply_overrides(sc.settings, overrides);
  const bool baseline_correction = sc.ground_motion.baseline_correction;
  sc.ground_motion = record.motion;  // the record's components; its window is the settings'
  sc.ground_motion.baseline_correction = baseline_correction;
  const double record_pga_g = horizontal_pga_m_s2(sc.motion()) / kStandardGravity_m_s2;
  if (sweep.scale_to_pga && !(record_pga_g > 0))
    throw InputError(sweep.file.string() + ": record '" + record.name + "' has no horizontal acceleration to scale to a PGA");
  const double factor = sweep.scale_to_pga ? level / record_pga_g : level;
  for (auto& component : sc.ground_motion.component)
    if (component) component->scale *= factor;

  SeismicRunOptions options;
  if (sweep.members > 1) options.member = c.member;
  options.checkpoint_wall_s = checkpoint_wall_s;
  if (sweep.failure.stop_at_failure)
    options.stop_when = [&](const SeismicRunResult& so_far) { return has_failed(sweep.failure, so_far); };
  const fs::path folder = case_folder(sweep, c, out);
  // Outputs stamped but without their row (killed between the two) run again: the row
  // needs the run's result.
  fs::remove(folder / "inputs.key");
  auto start = [&](const SeismicRunOptions& o) { return std::make_unique<SeismicRun>(sc, o); };
  SeismicRunResult r;
  const MemberStatus status = run_in_folder_or_throw(folder, case_key(sweep, c), c.key, options, threads, start, event, &sc, &r);
  if (status == MemberStatus::interrupted) throw std::runtime_error("interrupted (the same command goes on from its checkpoint)");
  const bool failed = has_failed(sweep.failure, r);
  std::ostringstream row;
  row.precision(9);
  row << c.key << "," << factor << "," << record_pga_g * factor << "," << (failed ? 1 : 0) << "," << result_csv_values(r) << ","
      << host_name() << "\n";
  return row.str();
}

// The cases not yet in sweep.csv with current outputs (a sweep resumes where it stopped;
// a case whose program or inputs changed runs again); rewrites the table without the rows
// of other cases and a row a crash cut short, and leaves its text in *table_text. A table of
// other columns (another version's) is refused rather than mixed with this one's rows.
std::vector<int> cases_to_run(const SweepFile& sweep, const fs::path& out, const std::vector<Case>& cases,
                              std::string* table_text) {
  const fs::path table = out / "sweep.csv";
  std::string header;
  std::getline(std::ifstream(table), header);
  if (!header.empty() && header + "\n" != sweep_csv_header())
    throw InputError(table.string() + ": its columns are not this version's (\"" + header.substr(0, 40) +
                     "...\"); move it away, or give the sweep another --out");
  std::map<std::string, int> case_of;  // "scenario,record,level,member" -> case
  for (int i = 0; i < static_cast<int>(cases.size()); ++i) case_of[cases[i].key] = i;
  std::set<int> done;
  std::string kept = sweep_csv_header();
  for (const std::string& row : finished_sweep_rows(table)) {
    const std::vector<std::string> f = row_fields(row);
    const auto c = f.size() >= 4 ? case_of.find(f[0] + "," + f[1] + "," + f[2] + "," + f[3]) : case_of.end();
    if (c == case_of.end() || !outputs_current(case_folder(sweep, cases[c->second], out), case_key(sweep, cases[c->second])))
      continue;
    done.insert(c->second);
    kept += row;
  }
  write_text_atomically(table, kept);
  *table_text = kept;
  std::vector<int> pending;
  for (int i = 0; i < static_cast<int>(cases.size()); ++i)
    if (!done.count(i)) pending.push_back(i);
  return pending;
}

}  // namespace

// Rank 0's queue serves its own worker threads and the other ranks' requests in one
// function: both share the lock, the open table and the counts.
SweepOutcome run_sweep(const SweepFile& sweep, const SweepOptions& o, const MpiSession& mpi) {
  const bool root = mpi.rank() == 0;
  std::mutex event_lock;  // the runs' progress lines come from several worker threads
  auto event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> guard(event_lock);
    if (o.on_event) o.on_event(text);
  };
  // The variants of one (record, level, member) next to each other: a sweep stopped part
  // way has compared what it has run.
  std::vector<Case> cases;
  for (int m = 0; m < std::max(1, sweep.members); ++m)
    for (int r = 0; r < static_cast<int>(sweep.records.size()); ++r)
      for (int l = 0; l < static_cast<int>(sweep.levels.size()); ++l)
        for (int k = 0; k < static_cast<int>(sweep.scenarios.size()); ++k)
          cases.push_back({k, r, l, m, scenario_name(sweep, k) + "," + sweep.records[r].name + "," +
                                           level_label(sweep.levels[l]) + "," + std::to_string(m)});
  const int runs_here = mpi.size() > 1 ? 1 : std::max(1, o.jobs);
  const int node_share = mpi.size() > 1 ? mpi.ranks_on_this_node() : runs_here;
  const int threads = decide_thread_count(o.threads_per_job, node_share);
  SweepOutcome outcome;
  // A case's answer for rank 0: its row, or "!" and what went wrong.
  auto row_of = [&](int i) {
    try {
      return run_case(sweep, cases[i], threads, o.out, o.checkpoint_wall_s, event);
    } catch (const std::exception& e) {
      return "!" + cases[i].key + ": " + e.what();
    }
  };
  if (!root) {
    run_jobs({}, 1, &mpi, [&](int i) {
      const std::string row = row_of(i);
      ++(row[0] == '!' ? outcome.failed : outcome.ran);
      return row;
    });
    return outcome;
  }

  // ---- rank 0 (or the only process): the queue, sweep.csv and the curves ----
  fs::create_directories(o.out);
  const FolderLock claim(o.out);  // its case folders are claimed by their runs
  const fs::path table = o.out / "sweep.csv";
  std::string table_text;  // sweep.csv as it is on disk
  const std::vector<int> pending = cases_to_run(sweep, o.out, cases, &table_text);
  outcome.kept = static_cast<int>(cases.size() - pending.size());
  event("sweep: " + std::to_string(cases.size()) + " runs (" + std::to_string(sweep.scenarios.size()) + " scenarios x " +
        std::to_string(sweep.records.size()) + " records x " +
        std::to_string(sweep.levels.size()) + " levels" +
        (sweep.members > 1 ? " x " + std::to_string(sweep.members) + " members" : "") + "), " +
        std::to_string(outcome.kept) + " done before; " +
        std::to_string(mpi.size() > 1 ? mpi.size() : runs_here) + (mpi.size() > 1 ? " MPI ranks" : " at a time") + ", " +
        std::to_string(threads) + " threads each");

  std::mutex lock;  // sweep.csv and the counts; outside any time step
  auto finish = [&](const std::string& message, int rank) {
    const std::lock_guard<std::mutex> guard(lock);
    if (message[0] == '!') {
      ++outcome.failed;
      event("FAILED " + message.substr(1) + " (rank " + std::to_string(rank) + ")");
      return;
    }
    std::size_t key_end = 0;  // the row's first four fields: its case
    for (int field = 0; field < 4 && key_end != std::string::npos; ++field) key_end = message.find(',', key_end + (field > 0));
    const std::string key = message.substr(0, key_end), on_rank = " (rank " + std::to_string(rank) + ")";
    // The whole table rewritten, not a row appended: a full disk then loses this row (the
    // case runs again next time), never cuts one short for the next row to run into.
    try {
      write_text_atomically(table, table_text + message);
    } catch (const std::exception& e) {
      ++outcome.failed;
      event("FAILED " + key + ": " + e.what() + on_rank);
      return;
    }
    table_text += message;
    ++outcome.ran;
    event(key + ": done" + on_rank);
  };
  run_jobs(
      pending, runs_here, &mpi,
      [&](int i) {  // run_in_folder says whether it started or went on from a checkpoint
        const std::string row = row_of(i);
        finish(row, 0);
        return row;
      },
      finish, [&](int next, int rank) { event(cases[next].key + ": started on rank " + std::to_string(rank)); });

  outcome.fragility = write_sweep_curves(sweep, o.out, finished_sweep_rows(table));
  if (!stop_requested()) {
    const std::string failed = run_report_script("sweep_plots.py", o.out);
    outcome.plots_written = failed.empty();
    if (!failed.empty()) event("plots: FAILED: " + failed);
  }
  return outcome;
}

}  // namespace ishibashi
