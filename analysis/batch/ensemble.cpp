#include "analysis/batch/ensemble.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/batch/job_queue.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/member_draw.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/input_error.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

fs::path member_folder(const fs::path& out, int member) {
  char name[32];
  std::snprintf(name, sizeof name, "member_%03d", member);
  return out / name;
}

// What a member's outputs depend on: the scenario and its files, the settings it runs with,
// the ensemble's draws and the member.
std::string member_key(const Scenario& sc, int member) {
  std::ostringstream in;
  in.precision(17);
  in << "ensemble member " << member << " of " << scenario_fingerprint(sc);
  for_each_run_setting([&](const SettingInfo& info, auto m) {
    if (std::string(info.key) != "threads") in << ' ' << info.key << '=' << setting_value(sc.settings.*m);
  });
  const EnsembleSpec& e = sc.ensemble;
  in << " seed " << e.seed << " tolerance " << e.position_tolerance_m << " friction " << e.friction_angle_deg[0] << ' '
     << e.friction_angle_deg[1] << " amplitude " << e.amplitude[0] << ' ' << e.amplitude[1];
  return inputs_key(in.str());
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// {"median", "min", "max", "count"} of the values (null where there are none).
nlohmann::ordered_json spread(const std::vector<double>& v) {
  nlohmann::ordered_json j;
  j["median"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(median(v));
  j["min"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::min_element(v.begin(), v.end()));
  j["max"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::max_element(v.begin(), v.end()));
  j["count"] = v.size();
  return j;
}

nlohmann::ordered_json probability(int hits, int trials) {
  const std::array<double, 2> ci = wilson_interval(hits, trials);
  nlohmann::ordered_json j;
  j["p"] = trials > 0 ? double(hits) / trials : 0.0;
  j["lo"] = ci[0];
  j["hi"] = ci[1];
  j["members"] = hits;
  return j;
}

// The first frame of history.csv with a fallen stone while shaking: seconds of shaking
// (-1: none).
double first_fall_s(const fs::path& history, double settle_time_s) {
  std::ifstream in(history);
  std::string line;
  if (!std::getline(in, line)) return -1;
  int time_col = -1, phase_col = -1, fallen_col = -1, col = 0;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ','); ++col) {
    if (name == "time_s") time_col = col;
    if (name == "phase") phase_col = col;
    if (name == "fallen_stones") fallen_col = col;
  }
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) f.push_back(cell);
    if (static_cast<int>(f.size()) <= std::max({time_col, phase_col, fallen_col})) continue;
    if (f[phase_col] == "shake" && std::stoi(f[fallen_col]) > 0) return std::stod(f[time_col]) - settle_time_s;
  }
  return -1;
}

enum class MemberStatus { current, ran, interrupted, failed };

// Member i of sc in out/member_NNN: kept when finished with the same inputs, else run, or
// continued from its checkpoint when the folder's run was started with the same inputs.
MemberStatus run_member(const Scenario& sc, int i, const fs::path& out, int threads, double checkpoint_wall_s,
                        const std::function<void(const std::string&)>& event) {
  const fs::path folder = member_folder(out, i);
  const std::string key = member_key(sc, i), name = "member " + std::to_string(i);
  if (outputs_current(folder, key)) {
    event(name + ": current, kept");
    return MemberStatus::current;
  }
  try {
    use_threads(threads);
    SeismicRunOptions options;
    options.out = folder;
    options.member = i;
    options.checkpoint_wall_s = checkpoint_wall_s;
    RunOverrides overrides;
    overrides.set(&RunSettings::threads, threads);
    std::unique_ptr<SeismicRun> run;
    std::string started;  // the key of the run the folder's checkpoint belongs to
    std::getline(std::ifstream(folder / "started.key"), started);
    if (started == key && fs::exists(folder / "checkpoint.bin")) {
      run = SeismicRun::resume(options, overrides);
      event(name + ": goes on from its checkpoint");
    }
    if (!run) {
      fs::remove_all(folder);  // no frames of an older run left behind
      fs::create_directories(folder);
      write_text_atomically(folder / "started.key", key + "\n");
      Scenario member = sc;
      apply_overrides(member.settings, overrides);
      run = std::make_unique<SeismicRun>(member, options);
      event(name + ": started");
    }
    const SeismicRunResult r = run->run();
    if (r.interrupted) {
      event(name + ": interrupted (its checkpoint is kept: the ensemble goes on from it)");
      return MemberStatus::interrupted;
    }
    fs::remove(folder / "checkpoint.bin");
    stamp_outputs(folder, key);  // last: the outputs are complete
    event(name + ": done, " + std::to_string(r.fallen_stones) + " fallen stones" + (r.collapse ? ", collapse" : ""));
    return MemberStatus::ran;
  } catch (const std::exception& e) {
    event(name + ": FAILED: " + e.what());
    return MemberStatus::failed;
  }
}

// ensemble.csv and ensemble.json from every finished member's summary.json (its counts
// into `outcome`).
void write_tables(const Scenario& sc, const fs::path& out, EnsembleOutcome& outcome) {
  const int n = sc.ensemble.members;
  std::ostringstream csv;
  csv << "member,seed,amplitude,friction_angle_deg";
  for (const ResultColumn& c : result_columns()) csv << ',' << c.name;
  csv << ",first_fall_s\n";
  std::vector<double> fallen, first_opening, first_fall, crown_drop;
  for (int i = 0; i < n; ++i) {
    const fs::path folder = member_folder(out, i);
    if (!outputs_current(folder, member_key(sc, i))) continue;
    const nlohmann::json s = nlohmann::json::parse(std::ifstream(folder / "summary.json"));
    const MemberDraw draw = draw_member(sc.ensemble, i);
    const double fall = first_fall_s(folder / "history.csv", s["settle_time_s"].get<double>());
    csv << i << ',' << sc.ensemble.seed << ',' << draw.amplitude << ',' << draw.friction_angle_deg;
    for (const ResultColumn& c : result_columns()) {
      const nlohmann::json& v = s[c.name];
      csv << ',';
      if (v.is_boolean()) csv << (v.get<bool>() ? "yes" : "no");
      else if (v.is_string()) csv << v.get<std::string>();
      else if (!v.is_null()) csv << v.dump();
    }
    csv << ',' << (fall < 0 ? std::string() : std::to_string(fall)) << '\n';
    ++outcome.finished;
    outcome.collapses += s["collapse"].get<bool>();
    outcome.stones_fell += s["fallen_stones"].get<int>() > 0;
    outcome.ring_stones_fell += s["fallen_ring_stones"].get<int>() > 0;
    fallen.push_back(s["fallen_stones"].get<int>());
    if (!s["first_opening_s"].is_null()) first_opening.push_back(s["first_opening_s"].get<double>());
    if (fall >= 0) first_fall.push_back(fall);
    crown_drop.push_back(s["largest_crown_drop_m"].get<double>());
  }
  write_text_atomically(out / "ensemble.csv", csv.str());

  nlohmann::ordered_json j;
  j["scenario"] = fs::absolute(sc.file).string();
  j["members"] = n;
  j["finished"] = outcome.finished;
  j["seed"] = sc.ensemble.seed;
  j["position_tolerance_m"] = sc.ensemble.position_tolerance_m;
  j["friction_angle_deg"] = sc.ensemble.varies_friction() ? nlohmann::ordered_json(sc.ensemble.friction_angle_deg) : nullptr;
  j["amplitude"] = sc.ensemble.amplitude;
  j["interval"] = "95 % Wilson score interval of each proportion";
  j["collapse"] = probability(outcome.collapses, outcome.finished);
  j["stones_fall"] = probability(outcome.stones_fell, outcome.finished);
  j["ring_stones_fall"] = probability(outcome.ring_stones_fell, outcome.finished);
  j["fallen_stones"] = spread(fallen);
  j["first_opening_s"] = spread(first_opening);  // count: the members in which a joint opened
  j["first_fall_s"] = spread(first_fall);
  j["largest_crown_drop_m"] = spread(crown_drop);
  j["settings"] = nlohmann::ordered_json::object();
  for_each_run_setting([&](const SettingInfo& info, auto m) { j["settings"][info.key] = setting_value(sc.settings.*m); });
  write_text_atomically(out / "ensemble.json", j.dump(2) + "\n");
}

}  // namespace

std::array<double, 2> wilson_interval(int hits, int trials, double z) {
  if (trials <= 0) return {0.0, 1.0};
  const double n = trials, p = hits / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

EnsembleOutcome run_ensemble(const Scenario& scenario, const EnsembleOptions& o) {
  Scenario sc = scenario;
  if (o.members > 0) sc.ensemble.members = o.members;
  if (o.seed >= 0) sc.ensemble.seed = o.seed;
  const int n = sc.ensemble.members;
  if (n <= 0)
    throw InputError(sc.file.string() + ": an ensemble needs members: [ensemble] members = N in the scenario, or --members N");
  fs::create_directories(o.out);
  const int workers = std::max(1, std::min(o.jobs, n));
  const int threads = decide_thread_count(o.threads_per_member, workers);
  std::mutex report_lock;  // serialises on_event; outside any time step
  auto event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> lock(report_lock);
    if (o.on_event) o.on_event(text);
  };
  event("ensemble of " + std::to_string(n) + " members (seed " + std::to_string(sc.ensemble.seed) + "), " +
        std::to_string(workers) + " at a time, " + std::to_string(threads) + " threads each, outputs in " + o.out.string());
  std::array<std::atomic<int>, 4> counts{};  // by MemberStatus
  auto job = [&](int i) { ++counts[static_cast<int>(run_member(sc, i, o.out, threads, o.checkpoint_wall_s, event))]; };
  JobQueue queue(every_job(n));
  queue.start(workers - 1, job);
  queue.work(job);
  queue.join();

  EnsembleOutcome outcome;
  outcome.members = n;
  outcome.current = counts[static_cast<int>(MemberStatus::current)];
  outcome.ran = counts[static_cast<int>(MemberStatus::ran)];
  outcome.interrupted = counts[static_cast<int>(MemberStatus::interrupted)];
  outcome.failed = counts[static_cast<int>(MemberStatus::failed)];
  write_tables(sc, o.out, outcome);
  return outcome;
}

}  // namespace ishibashi
