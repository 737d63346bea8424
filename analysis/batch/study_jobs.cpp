#include "analysis/batch/study_jobs.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "analysis/batch/ensemble.h"
#include "analysis/batch/job_queue.h"
#include "analysis/dynamics/frequencies.h"
#include "analysis/model/compile_model.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/seismic_run.h"
#include "io/atomic_file.h"
#include "io/scenario_file.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

constexpr const char* kSingleRunColumns = ",1,,,,,,,,,,,,,";
constexpr double kStudyCheckpointWallS = 600;  // a stopped study loses at most 10 min of each run

std::string job_key(const Job& job, const StudyFile& study, const RunOverrides& overrides) {
  std::ostringstream in;
  in << (job.kind == JobKind::run ? " run " : " frequencies ");
  if (job.kind == JobKind::run)  // the scenario, its model file and records
    in << scenario_fingerprint(*job.scenario) << " duration " << study.duration_s;
  else if (job.scenario)
    in << file_bytes(job.input) << file_bytes(job.scenario->model_file);
  else
    in << file_bytes(job.input);
  if (job.kind == JobKind::run && study.members >= 2) in << " members " << study.members;
  if (job.kind == JobKind::run)
    for_each_run_setting([&](const SettingInfo& info, auto member) {
      if (overrides.given.count(info.key)) in << " " << info.key << " " << setting_value(overrides.values.*member);
    });
  if (job.kind == JobKind::frequencies)
    in << " modes " << study.modes << " impulse " << study.impulse_s << " rule " << job.joint_rule;
  return inputs_key(in.str());
}

// The run's ground motion as the report plots it: 200 samples per second.
void write_ground_motion(const Scenario& sc, const fs::path& folder) {
  const GroundMotion g = prepare_ground_motion(sc.motion(), 0.005);
  std::ostringstream csv;
  csv << "time_s,ax_m_s2,ay_m_s2,az_m_s2\n";
  for (std::size_t k = 0; k < g.accel_m_s2.size(); ++k)
    csv << k * g.dt_s << "," << g.accel_m_s2[k].x() << "," << g.accel_m_s2[k].y() << "," << g.accel_m_s2[k].z() << "\n";
  write_text_atomically(folder / "ground_motion.csv", csv.str());
}

Scenario run_scenario_of(const Job& job, const StudyFile& study, int threads) {
  Scenario sc = *job.scenario;
  if (study.duration_s >= 0) sc.settings.duration_s = study.duration_s;
  sc.settings.threads = threads;
  return sc;
}

// A run's ensemble (study members >= 2) in its folder, its members checkpointed as the
// study's runs are.
EnsembleOptions ensemble_options(const Job& job, const StudyFile& study, int threads, bool reports) {
  EnsembleOptions options;
  options.out = job.folder;
  options.members = study.members;
  options.threads_per_member = threads;
  options.checkpoint_wall_s = kStudyCheckpointWallS;
  options.member_reports = reports;
  options.report_title = study.name + ": " + job.input.filename().string();
  return options;
}

}  // namespace

const std::string kRunHeader = "scenario,model,mortar_pa," + result_csv_header() +
                               ",dt_s,threads,monitored_block,members,typical_member,worst_member,p_collapse,p_collapse_lo,"
                               "p_collapse_hi,p_stones_fall,p_stones_fall_lo,p_stones_fall_hi,p_ring_stones_fall,"
                               "p_ring_stones_fall_lo,p_ring_stones_fall_hi,fallen_min,fallen_max\n";
const char* const kFrequencyHeader =
    "model,file,folder,subdivision,joint_rule,sub_contacts,mode_x_hz,mode_y_hz,mode_z_hz,impulse_x_hz,impulse_y_hz,impulse_z_hz,"
    "impulse_xz_hz,impulse_yz_hz\n";

std::string job_name(const Job& job) {
  return (job.kind == JobKind::run ? "run " : "frequencies ") + job.folder.filename().string();
}

bool is_current(const Job& job) { return fs::exists(job.folder / "row.csv") && outputs_current(job.folder, job.key); }

bool resumable(const Job& job) {
  const fs::path started = job.folder / "started.key";
  return job.kind == JobKind::run && fs::exists(job.folder / "checkpoint.bin") && fs::exists(started) &&
         file_bytes(started) == job.key + "\n";
}

// An ensemble's row of runs.csv (its members in the job's folder, finished ones kept): the
// most common outcome's member's result, then the probabilities.
std::string ensemble_job(const Job& job, const StudyFile& study, int threads, bool reports) {
  fs::create_directories(job.folder);
  const Scenario sc = run_scenario_of(job, study, threads);
  const EnsembleOutcome e = run_ensemble(sc, ensemble_options(job, study, threads, reports));
  if (e.interrupted > 0) throw std::runtime_error("interrupted (its members' checkpoints are kept: the next study goes on from them)");
  if (e.failed > 0 || e.finished < e.members) throw std::runtime_error(std::to_string(e.failed) + " members failed");
  write_ground_motion(sc, job.folder);
  const fs::path typical = member_folder(job.folder, e.typical_member);
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(typical / "summary.json"));
  const nlohmann::json probabilities = nlohmann::json::parse(std::ifstream(job.folder / "ensemble.json"));
  std::ostringstream row;
  row.precision(9);
  row << kRunHeader << job.input.stem().string() << ",\"" << sc.model.name << "\"," << sc.model.bridge.mortar_pa << ","
      << summary_csv_values(summary) << "," << summary["dt_s"].get<double>() << "," << threads << ","
      << summary["monitored_block"].get<int>() << "," << e.members << "," << typical.filename().string() << ","
      << member_folder(job.folder, e.worst_member).filename().string();
  for (const char* p : {"collapse", "stones_fall", "ring_stones_fall"})
    row << "," << probabilities[p]["p"].get<double>() << "," << probabilities[p]["lo"].get<double>() << ","
        << probabilities[p]["hi"].get<double>();
  row << "," << probabilities["fallen_stones"]["min"].get<int>() << "," << probabilities["fallen_stones"]["max"].get<int>() << "\n";
  return row.str();
}

// Member `member` of a run's ensemble, in the run's folder: "ran", "current" (kept),
// "interrupted" or "failed".
std::string ensemble_member(const Job& job, int member, const StudyFile& study, int threads, bool reports) {
  fs::create_directories(job.folder);
  EnsembleOptions options = ensemble_options(job, study, threads, reports);
  options.first_member = member;
  options.end_member = member + 1;
  const EnsembleOutcome e = run_ensemble(run_scenario_of(job, study, threads), options);
  return e.ran ? "ran" : e.current ? "current" : e.interrupted ? "interrupted" : "failed";
}

// A run's row of runs.csv, and its ground motion as the report plots it. A resumable run
// goes on from its last checkpoint; otherwise it starts afresh. `on_fraction`: how much of
// its shaking is done, after each frame.
std::string seismic_job(const Job& job, const StudyFile& study, int threads, const std::function<void(double)>& on_fraction,
                        bool resumed) {
  if (!resumed) {
    fs::remove_all(job.folder);  // no frames of an older, longer run left behind
    fs::create_directories(job.folder);
    write_text_atomically(job.folder / "started.key", job.key + "\n");
  }
  SeismicRunOptions options;
  options.out = job.folder;
  options.on_frame = [&](const State&, double done) { on_fraction(done); };
  options.checkpoint_wall_s = kStudyCheckpointWallS;
  RunOverrides overrides;
  overrides.set(&RunSettings::threads, threads);
  std::unique_ptr<SeismicRun> run;
  if (resumed) {
    run = SeismicRun::resume(options, overrides);
  } else {
    run = std::make_unique<SeismicRun>(run_scenario_of(job, study, threads), options);
  }
  const SeismicRunResult r = run->run();
  if (r.interrupted) throw std::runtime_error("interrupted (its checkpoint is kept: the next study goes on from it)");
  fs::remove(job.folder / "checkpoint.bin");
  const Scenario& sc = run->scenario();
  write_ground_motion(sc, job.folder);
  std::ostringstream row;
  row.precision(9);
  row << kRunHeader << job.input.stem().string() << ",\"" << sc.model.name << "\"," << sc.model.bridge.mortar_pa << ","
      << result_csv_values(r) << "," << run->dt_s() << "," << threads << "," << run->monitored_block() << kSingleRunColumns
      << "\n";
  return row.str();
}

// A frequency analysis's row of frequencies.csv.
std::string frequency_job(const Job& job, const StudyFile& study) {
  fs::remove_all(job.folder);
  fs::create_directories(job.folder);
  RunOverrides rule;
  if (!job.joint_rule.empty()) rule.set(&RunSettings::joint_rule, parse_joint_rule(job.joint_rule));
  const LoadedModel loaded = job.scenario ? load_scenario_model(*job.scenario, rule) : load_model_or_scenario(job.input, rule);
  FrequencyOptions options;
  options.modes = study.modes;
  options.impulse_s = study.impulse_s;
  const FrequencyAnalysis a = analyse_frequencies(loaded, options, job.folder);
  std::ostringstream row;
  row.precision(9);
  row << kFrequencyHeader << "\"" << loaded.name << "\"," << job.input.stem().string() << ","
      << job.folder.filename().string() << "," << loaded.options().subdivision << "," << joint_rule_name(loaded.options().joint_rule) << "," << a.sub_contacts;
  for (double f : a.first_mode_hz) row << "," << f;
  // The first clear peak of each step read along itself at the crown unit, then of the x
  // and y steps read in z at the face unit beside it.
  for (auto [step, read] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 2}, {1, 2}}) {
    row << ",";
    const int monitor = step == read ? ImpulseSpec::kCrownUnit : ImpulseSpec::kFaceUnitBesideCrown;
    for (const ImpulseResult& i : a.impulses)
      if (i.spec.excitation_axis == step && i.spec.response_axis == read && i.requested.monitor_block == monitor)
        row << first_peak_hz(i.spectrum);
  }
  row << "\n";
  return row.str();
}

std::vector<Job> make_jobs(const StudyFile& study, const fs::path& out, const RunOverrides& overrides) {
  std::vector<Job> jobs;
  for (const fs::path& s : study.scenarios) {
    jobs.push_back({JobKind::run, s, out / "runs" / s.stem(), read_scenario(s)});
    apply_overrides(jobs.back().scenario->settings, overrides);
  }
  for (const fs::path& m : study.models) {
    std::optional<Scenario> scenario;
    if (is_scenario_file(m)) scenario = read_scenario(m);
    if (study.joint_rules.empty()) jobs.push_back({JobKind::frequencies, m, out / "frequencies" / m.stem(), scenario});
    for (const std::string& rule : study.joint_rules)
      jobs.push_back({JobKind::frequencies, m, out / "frequencies" / (m.stem().string() + "_" + rule), scenario, rule});
  }
  for (Job& job : jobs) job.key = job_key(job, study, overrides);
  return jobs;
}

}  // namespace ishibashi
