#include "analysis/batch/study.h"


#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <vector>

#include "analysis/batch/ensemble.h"
#include "analysis/batch/job_queue.h"
#include "analysis/batch/mpi_ranks.h"
#include "analysis/batch/study_progress.h"
#include "analysis/dynamics/frequencies.h"
#include "analysis/model/compile_model.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/scenario_file.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;

enum class JobKind { frequencies, run };

struct Job {
  JobKind kind;
  fs::path input;   // model or scenario file
  fs::path folder;  // its outputs
  std::optional<Scenario> scenario{};  // the input, parsed once, when it is a scenario
  std::string joint_rule{};  // a frequency analysis under this rule; empty: the model's own
  std::string key{};  // fingerprint of everything the outputs depend on
  std::string status = "pending", error{};
  double seconds = 0;
};

std::string job_name(const Job& job) {
  return (job.kind == JobKind::run ? "run " : "frequencies ") + job.folder.filename().string();
}

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

// A CSV field in quotes, inner quotes doubled (RFC 4180, as Python's csv reads it).
std::string csv_quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

bool is_current(const Job& job) { return fs::exists(job.folder / "row.csv") && outputs_current(job.folder, job.key); }

// Which run, its result (run_result.h) and how it ran.
// A run of an ensemble (study members >= 2) gives the result of its most common outcome's
// member, then its probabilities (a single run: members 1, the rest empty).
const std::string kRunHeader = "scenario,model,mortar_pa," + result_csv_header() +
                               ",dt_s,threads,monitored_block,members,typical_member,worst_member,p_collapse,p_collapse_lo,"
                               "p_collapse_hi,p_stones_fall,p_stones_fall_lo,p_stones_fall_hi,p_ring_stones_fall,"
                               "p_ring_stones_fall_lo,p_ring_stones_fall_hi,fallen_min,fallen_max\n";
constexpr const char* kSingleRunColumns = ",1,,,,,,,,,,,,,";
constexpr const char* kFrequencyHeader =
    "model,file,folder,subdivision,joint_rule,sub_contacts,mode_x_hz,mode_y_hz,mode_z_hz,impulse_x_hz,impulse_y_hz,impulse_z_hz,"
    "impulse_xz_hz,impulse_yz_hz\n";
constexpr double kStudyCheckpointWallS = 600;  // a stopped study loses at most 10 min of each run

// A run stopped part way (Ctrl-C, a session's or a cluster job's end) with a checkpoint
// of the same job key (same program, inputs and duration).
bool resumable(const Job& job) {
  const fs::path started = job.folder / "started.key";
  return job.kind == JobKind::run && fs::exists(job.folder / "checkpoint.bin") && fs::exists(started) &&
         file_bytes(started) == job.key + "\n";
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

// An ensemble's row of runs.csv (its members in the job's folder, finished ones kept): the
// most common outcome's member's result, then the probabilities.
std::string ensemble_job(const Job& job, const StudyFile& study, int threads) {
  fs::create_directories(job.folder);
  const Scenario sc = run_scenario_of(job, study, threads);
  EnsembleOptions options;
  options.out = job.folder;
  options.members = study.members;
  options.threads_per_member = threads;
  options.checkpoint_wall_s = kStudyCheckpointWallS;
  const EnsembleOutcome e = run_ensemble(sc, options);
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

// One table of every job's row (their header once).
void gather_rows(const std::vector<Job>& jobs, JobKind kind, const std::string& header, const fs::path& file) {
  std::string table = header;
  for (const Job& job : jobs) {
    if (job.kind != kind || !fs::exists(job.folder / "row.csv") || job.status == "failed") continue;
    const std::string rows = file_bytes(job.folder / "row.csv");
    table += rows.substr(rows.find('\n') + 1);
  }
  write_text_atomically(file, table);
}

// The long runs first: the frequency analyses fill the gaps at the end.
// A run's settings replaced by `overrides` (study --damping ...), which its key includes.
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

// The study's tables: what ran (jobs.csv), a row per run and per analysis, what the
// report needs to know of the study, and the published study's own figures and verdicts.
void write_tables(const std::vector<Job>& jobs, const StudyFile& study, const fs::path& out) {
  std::ostringstream list;
  list << "kind,input,status,seconds,error\n";
  for (const Job& job : jobs)
    list << (job.kind == JobKind::run ? "run," : "frequencies,") << job.input.string() << "," << job.status << ","
         << job.seconds << "," << csv_quoted(job.error) << "\n";
  fs::create_directories(out);
  write_text_atomically(out / "jobs.csv", list.str());
  gather_rows(jobs, JobKind::run, kRunHeader, out / "runs.csv");
  gather_rows(jobs, JobKind::frequencies, kFrequencyHeader, out / "frequencies.csv");
  std::ostringstream about;
  about << "name," << study.name << "\nstudy_file," << fs::absolute(study.file).string() << "\n";
  about << "snapshot_times_s,";
  for (std::size_t k = 0; k < study.snapshot_times_s.size(); ++k) about << (k ? " " : "") << study.snapshot_times_s[k];
  about << "\n";
  write_text_atomically(out / "study.csv", about.str());
  std::ostringstream reference;  // for the report: the study's own figures and verdicts
  reference << "kind,key,x_hz,y_hz,z_hz,says\n";
  for (const auto& [stem, hz] : study.reference_frequencies_hz)
    reference << "frequencies," << stem << "," << hz[0] << "," << hz[1] << "," << hz[2] << ",\n";
  for (const auto& [stem, says] : study.reference_says) reference << "says," << stem << ",,,," << csv_quoted(says) << "\n";
  for (const auto& [stem, verdict] : study.reference_outcome) reference << "outcome," << stem << ",,,," << verdict << "\n";
  write_text_atomically(out / "reference.csv", reference.str());
}

}  // namespace

StudyOutcome run_study(const StudyFile& study_file, const StudyOptions& o) {
  StudyFile study = study_file;
  if (o.members >= 0) study.members = o.members;
  std::vector<Job> jobs = make_jobs(study, o.out, o.run_overrides);

  const bool ranks = o.mpi && o.mpi->size() > 1;  // under mpirun: one job per rank at a time
  const bool root = !ranks || o.mpi->rank() == 0;
  const int workers = ranks ? o.mpi->size() : std::max(1, std::min<int>(o.jobs, static_cast<int>(jobs.size())));
  const int threads = decide_thread_count(o.threads_per_job, ranks ? o.mpi->ranks_on_this_node() : workers);
  const std::string rank_here = ranks ? " (rank " + std::to_string(o.mpi->rank()) + ")" : "";
  std::mutex report_lock;  // serialises on_event; outside any time step
  auto event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> lock(report_lock);
    if (o.on_event) o.on_event(text);
  };
  if (root)
    event("study '" + study.name + "': " + std::to_string(jobs.size()) + " jobs, " +
          (ranks ? std::to_string(workers) + " MPI ranks" : std::to_string(workers) + " at a time") + ", " +
          std::to_string(threads) + " threads each, outputs in " + o.out.string());

  std::vector<JobProgress> progress_jobs;
  for (const Job& job : jobs)
    progress_jobs.push_back({job_name(job), job.kind == JobKind::run});
  // The study's progress lines come from rank 0 alone, which hears of the other ranks' jobs
  // as it hands them out and as they end.
  StudyProgress progress(std::move(progress_jobs), workers, o.progress_every_s,
                         root ? std::function<void(const std::string&)>(event) : [](const std::string&) {});

  auto run_job = [&](int i) {
    Job& job = jobs[i];
    const std::string name = job_name(job) + rank_here;
    if (!o.force && is_current(job)) {
      job.status = "current";
      event(name + ": current, kept");
      progress.finished(i, JobProgress::skipped);
      return;
    }
    const bool ensemble = job.kind == JobKind::run && study.members >= 2;
    if (ensemble && o.force) fs::remove_all(job.folder);
    const bool resumed = !o.force && resumable(job);
    event(name + (ensemble ? ": an ensemble of " + std::to_string(study.members) + " members (finished ones kept)"
                  : resumed ? ": goes on from its checkpoint" : ": started"));
    progress.started(i, resumed);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      use_threads(threads);
      const std::string row =
          ensemble ? ensemble_job(job, study, threads)
          : job.kind == JobKind::run
              ? seismic_job(job, study, threads, [&progress, i](double done) { progress.advanced(i, done); }, resumed)
              : frequency_job(job, study);
      write_text_atomically(job.folder / "row.csv", row);
      stamp_outputs(job.folder, job.key);  // last: the outputs are complete
      job.status = "ran";
    } catch (const std::exception& e) {
      job.status = "failed";
      job.error = e.what();
    }
    job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char took[64];
    std::snprintf(took, sizeof took, " (%.1f s)", job.seconds);
    event(name + (job.status == "ran" ? ": done" : ": FAILED: " + job.error) + took);
    progress.finished(i, job.status == "ran" ? JobProgress::done : JobProgress::failed);
  };
  JobQueue queue(every_job(static_cast<int>(jobs.size())));
  if (!root) {  // "job status seconds error" back to rank 0 with each request, for jobs.csv
    work_for_rank_zero([&](int i) {
      run_job(i);
      const Job& job = jobs[i];
      return std::to_string(i) + "\t" + job.status + "\t" + std::to_string(job.seconds) + "\t" + job.error;
    });
    return {};
  }
  if (ranks) {
    queue.start(1, run_job);
    serve_other_ranks(
        queue, *o.mpi,
        [&](const std::string& answer, int) {
          std::istringstream in(answer);
          std::string index, seconds;
          std::getline(in, index, '\t');
          Job& job = jobs[std::stoul(index)];
          std::getline(in, job.status, '\t');
          std::getline(in, seconds, '\t');
          std::getline(in, job.error);
          job.seconds = std::stod(seconds);
          progress.finished(std::stoul(index), job.status == "ran"       ? JobProgress::done
                                               : job.status == "current" ? JobProgress::skipped
                                                                         : JobProgress::failed);
        },
        [&](int i, int) { progress.started(i); });
  } else {
    queue.start(workers - 1, run_job);
    queue.work(run_job);
  }
  queue.join();

  StudyOutcome outcome;
  for (const Job& job : jobs) {
    outcome.ran += job.status == "ran";
    outcome.current += job.status == "current";
    outcome.failed += job.status == "failed";
  }
  write_tables(jobs, study, o.out);

  if (o.report && !stop_requested()) {
    event("report: analysis/report/report.py " + o.out.string());
    outcome.report_written = run_report_script("report.py", o.out);
    if (!outcome.report_written) event("report: FAILED (needs python3 with matplotlib and vtk: bash scripts/setup.sh)");
  }
  return outcome;
}

}  // namespace ishibashi
