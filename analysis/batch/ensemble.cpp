#include "analysis/batch/ensemble.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <numeric>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/batch/job_queue.h"
#include "analysis/batch/member_runs.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/member_draw.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "geometry/input_error.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

// What a member's outputs depend on: the scenario and its files, the settings it runs with,
// the ensemble's draws and the member.
std::string member_key(const Scenario& sc, int member) {
  std::ostringstream in;
  in.precision(17);
  in << "ensemble member " << member << " of " << scenario_fingerprint(sc) << settings_key_text(sc.settings);
  const EnsembleSpec& e = sc.ensemble;
  in << " seed " << e.seed << " tolerance " << e.position_tolerance_m << " friction " << e.friction_angle_deg[0] << ' '
     << e.friction_angle_deg[1] << " amplitude " << e.amplitude[0] << ' ' << e.amplitude[1];
  return inputs_key(in.str());
}

// ensemble.csv and ensemble.json from every finished member's summary.json.
OutcomeCounts write_tables(const Scenario& sc, const fs::path& out) {
  const EnsembleSpec& e = sc.ensemble;
  OutcomeTable table;
  table.draw_columns = {"seed", "amplitude", "friction_angle_deg"};
  for (int i = 0; i < e.members; ++i) {
    const fs::path folder = member_folder(out, i);
    if (!outputs_current(folder, member_key(sc, i))) continue;
    const MemberDraw draw = draw_member(e, i);
    table.rows.push_back({i, folder, {std::to_string(e.seed), number_text(draw.amplitude), number_text(draw.friction_angle_deg)}});
  }
  nlohmann::ordered_json j;
  j["scenario"] = fs::absolute(sc.file).string();
  j["members"] = e.members;
  j["seed"] = e.seed;
  j["position_tolerance_m"] = e.position_tolerance_m;
  j["friction_angle_deg"] = e.varies_friction() ? nlohmann::ordered_json(e.friction_angle_deg) : nullptr;
  j["amplitude"] = e.amplitude;
  const OutcomeCounts counts = write_outcomes(table, out / "ensemble.csv", j);
  j["settings"] = nlohmann::ordered_json::object();
  for_each_run_setting([&](const SettingInfo& info, auto m) { j["settings"][info.key] = setting_value(sc.settings.*m); });
  write_text_atomically(out / "ensemble.json", j.dump(2) + "\n");
  return counts;
}

}  // namespace

EnsembleOutcome run_ensemble(const Scenario& scenario, const EnsembleOptions& o) {
  Scenario sc = scenario;
  if (o.members > 0) sc.ensemble.members = o.members;
  if (o.seed >= 0) sc.ensemble.seed = o.seed;
  const int n = sc.ensemble.members;
  if (n <= 0)
    throw InputError(sc.file.string() + ": an ensemble needs members: [ensemble] members = N in the scenario, or --members N");
  const int first = o.first_member, end = o.end_member < 0 ? n : o.end_member;
  if (first < 0 || end > n || first >= end)
    throw InputError("member range " + std::to_string(first) + ":" + std::to_string(end) + ": the ensemble of " +
                     sc.file.string() + " has members 0 to " + std::to_string(n - 1) +
                     "; FROM:TO runs members FROM to TO - 1, with 0 <= FROM < TO <= " + std::to_string(n));
  fs::create_directories(o.out);
  const bool ranks = o.mpi && o.mpi->size() > 1;
  const int workers = ranks ? 1 : std::max(1, std::min(o.jobs, end - first));
  const int threads = decide_thread_count(o.threads_per_member, ranks ? o.mpi->ranks_on_this_node() : workers);
  const bool root = !ranks || o.mpi->rank() == 0;
  std::mutex report_lock;  // serialises on_event; outside any time step
  auto event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> lock(report_lock);
    if (o.on_event) o.on_event(text);
  };
  const std::string share =
      first == 0 && end == n ? "" : ", members " + std::to_string(first) + " to " + std::to_string(end - 1) + " here";
  if (root)
    event("ensemble of " + std::to_string(n) + " members (seed " + std::to_string(sc.ensemble.seed) + ")" + share + ", " +
          (ranks ? std::to_string(o.mpi->size()) + " MPI ranks" : std::to_string(workers) + " at a time") + ", " +
          std::to_string(threads) + " threads each, outputs in " + o.out.string());
  std::array<std::atomic<int>, 4> counts{};  // by MemberStatus
  // A member run on this rank; its answer for rank 0: its status, as a number.
  auto job = [&](int i) {
    SeismicRunOptions options;
    options.member = i;
    options.checkpoint_wall_s = o.checkpoint_wall_s;
    auto start = [&](const SeismicRunOptions& member_options) {
      Scenario member = sc;
      member.settings.threads = threads;
      return std::make_unique<SeismicRun>(member, member_options);
    };
    const std::string name = "member " + std::to_string(i) + (ranks ? " (rank " + std::to_string(o.mpi->rank()) + ")" : "");
    const MemberStatus status = run_in_folder(member_folder(o.out, i), member_key(sc, i), name, options, threads, start, event);
    if (status == MemberStatus::ran && o.member_reports)
      if (const std::string failed = run_report_script("run_report.py", member_folder(o.out, i),
                                                       o.report_title + ", member " + std::to_string(i));
          !failed.empty())
        event(name + ": report.png not drawn: " + failed);
    ++counts[static_cast<int>(status)];
    return std::to_string(static_cast<int>(status));
  };
  std::vector<int> members(end - first);
  std::iota(members.begin(), members.end(), first);
  EnsembleOutcome outcome;
  outcome.members = n;
  run_jobs(members, workers, o.mpi, job, [&](const std::string& status, int) { ++counts[std::stoi(status)]; });

  outcome.current = counts[static_cast<int>(MemberStatus::current)];
  outcome.ran = counts[static_cast<int>(MemberStatus::ran)];
  outcome.interrupted = counts[static_cast<int>(MemberStatus::interrupted)];
  outcome.failed = counts[static_cast<int>(MemberStatus::failed)];
  if (!root) return outcome;
  const OutcomeCounts finished = write_tables(sc, o.out);
  outcome.finished = finished.finished;
  outcome.collapses = finished.collapses;
  outcome.stones_fell = finished.stones_fell;
  outcome.ring_stones_fell = finished.ring_stones_fell;
  outcome.typical_member = finished.typical;
  outcome.worst_member = finished.worst;
  outcome.failure_modes = finished.failure_modes;
  return outcome;
}

}  // namespace ishibashi
