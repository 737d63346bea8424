#include "analysis/batch/study.h"

#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>
#include <sstream>
#include <vector>

#include "analysis/batch/job_queue.h"
#include "analysis/batch/mpi_ranks.h"
#include "analysis/batch/study_jobs.h"
#include "analysis/batch/study_progress.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/folder_lock.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;

// A CSV field in quotes, inner quotes doubled (RFC 4180, as Python's csv reads it).
std::string csv_quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
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

// A job run on this rank: kept when current, else run (a run goes on from its
// checkpoint) and its row and stamp written; its status, time and error set in `job`.
// `members_ran`: an ensemble's members ran as jobs of their own (run_members_across_ranks),
// --force included.
void run_job(Job& job, int i, const StudyFile& study, const StudyOptions& o, int threads, const std::string& name,
             StudyProgress& progress, const std::function<void(const std::string&)>& event, bool members_ran) {
  if (!o.force && is_current(job)) {
    job.status = "current";
    event(name + ": current, kept");
    progress.finished(i, JobProgress::skipped);
    return;
  }
  const bool ensemble = job.kind == JobKind::run && study.members >= 2;
  if (ensemble && o.force && !members_ran) fs::remove_all(job.folder);
  const bool resumed = !o.force && resumable(job);
  event(name + (ensemble ? ": an ensemble of " + std::to_string(study.members) + " members (finished ones kept)"
                : resumed ? ": goes on from its checkpoint" : ": started"));
  progress.started(i, resumed);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    use_threads(threads);
    const std::string row =
        ensemble ? ensemble_job(job, study, threads, o.report)
        : job.kind == JobKind::run
            ? seismic_job(job, study, threads, [&progress, i](double done) { progress.advanced(i, done); }, resumed)
            : frequency_job(job, study);
    write_text_atomically(job.folder / "row.csv", row);
    stamp_outputs(job.folder, job.key);  // last: the outputs are complete
    job.status = "ran";
    if (job.kind == JobKind::run && !ensemble && o.report)  // the run at a glance, as `run` draws it
      if (const std::string failed = run_report_script("run_report.py", job.folder, study.name + ": " + job.input.filename().string());
          !failed.empty())
        event(name + ": report.png not drawn: " + failed);
  } catch (const std::exception& e) {
    job.status = "failed";
    job.error = e.what();
  }
  job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char took[64];
  std::snprintf(took, sizeof took, " (%.1f s)", job.seconds);
  event(name + (job.status == "ran" ? ": done" : ": FAILED: " + job.error) + took);
  progress.finished(i, job.status == "ran" ? JobProgress::done : JobProgress::failed);
}

// What a rank tells rank 0 of a job it ran, for jobs.csv: "index status seconds error".
std::string job_answer(int i, const Job& job) {
  return std::to_string(i) + "\t" + job.status + "\t" + std::to_string(job.seconds) + "\t" + job.error;
}

// Rank 0 reads it into its job; returns the job's index.
std::size_t read_job_answer(const std::string& answer, std::vector<Job>& jobs) {
  std::istringstream in(answer);
  std::string index, seconds;
  std::getline(in, index, '\t');
  Job& job = jobs.at(std::stoul(index));
  std::getline(in, job.status, '\t');
  std::getline(in, seconds, '\t');
  std::getline(in, job.error);
  job.seconds = std::stod(seconds);
  return std::stoul(index);
}

// Under mpirun, each ensemble run's members as jobs of their own, spread over the ranks
// (twelve runs of five members keep sixty ranks busy, not twelve); the runs' own jobs then
// find their members finished and make their tables and rows. The list of (run, member) is
// the same on every rank; rank 0 empties the runs' folders first under --force. Returns, on
// rank 0, each job's seconds of member runs (the jobs' own then take a moment).
std::vector<double> run_members_across_ranks(const std::vector<Job>& jobs, const StudyFile& study, const StudyOptions& o,
                                             int threads, const std::string& rank_here,
                                             const std::function<void(const std::string&)>& event) {
  const bool root = o.mpi->rank() == 0;
  std::vector<std::pair<int, int>> members;  // (job, member)
  std::vector<JobProgress> progress_members;
  for (int j = 0; j < static_cast<int>(jobs.size()); ++j)
    for (int k = 0; jobs[j].kind == JobKind::run && k < study.members; ++k) {
      members.emplace_back(j, k);
      progress_members.push_back({job_name(jobs[j]) + " member " + std::to_string(k), false});  // paced as a whole
      if (root && o.force && k == 0) fs::remove_all(jobs[j].folder);
    }
  StudyProgress progress(std::move(progress_members), o.mpi->size(), o.progress_every_s,
                         root ? event : [](const std::string&) {});
  auto state = [](const std::string& status) {
    return status == "ran" ? JobProgress::done : status == "current" ? JobProgress::skipped : JobProgress::failed;
  };
  std::vector<double> seconds(jobs.size(), 0.0);
  std::mutex seconds_lock;  // rank 0's own member and its main thread; outside any time step
  auto add_seconds = [&](int u, double s) {
    const std::lock_guard<std::mutex> guard(seconds_lock);
    seconds[members[u].first] += s;
  };
  // A member's answer for rank 0: "index seconds status".
  run_jobs(
      every_job(static_cast<int>(members.size())), 1, o.mpi,
      [&](int u) {
        const auto [j, k] = members[u];
        const std::string name = job_name(jobs[j]) + " member " + std::to_string(k) + rank_here;
        event(name + ": started");
        progress.started(u);
        const auto t0 = std::chrono::steady_clock::now();
        const std::string status = ensemble_member(jobs[j], k, study, threads, o.report);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        event(name + ": " + status);
        progress.finished(u, state(status));
        add_seconds(u, s);
        return std::to_string(u) + " " + std::to_string(s) + " " + status;
      },
      [&](const std::string& answer, int) {
        std::istringstream in(answer);
        int u = 0;
        double s = 0;
        std::string status;
        in >> u >> s >> status;
        progress.finished(u, state(status));
        add_seconds(u, s);
      },
      [&](int u, int) { progress.started(u); });
  return seconds;
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
  std::optional<FolderLock> claim;  // rank 0's: the jobs' folders are claimed by their runs
  if (root) {
    fs::create_directories(o.out);
    claim.emplace(o.out);
  }
  if (root)
    event("study '" + study.name + "': " + std::to_string(jobs.size()) + " jobs, " +
          (ranks ? std::to_string(workers) + " MPI ranks" : std::to_string(workers) + " at a time") + ", " +
          std::to_string(threads) + " threads each, outputs in " + o.out.string());

  const bool members_ran = ranks && study.members >= 2;
  const std::vector<double> member_seconds =
      members_ran ? run_members_across_ranks(jobs, study, o, threads, rank_here, event) : std::vector<double>(jobs.size());

  std::vector<JobProgress> progress_jobs;
  for (const Job& job : jobs)
    progress_jobs.push_back({job_name(job), job.kind == JobKind::run});
  // The study's progress lines come from rank 0 alone, which hears of the other ranks' jobs
  // as it hands them out and as they end.
  StudyProgress progress(std::move(progress_jobs), workers, o.progress_every_s,
                         root ? std::function<void(const std::string&)>(event) : [](const std::string&) {});

  run_jobs(
      every_job(static_cast<int>(jobs.size())), workers, o.mpi,
      [&](int i) {
        run_job(jobs[i], i, study, o, threads, job_name(jobs[i]) + rank_here, progress, event, members_ran);
        return job_answer(i, jobs[i]);
      },
      [&](const std::string& answer, int) {
        const std::size_t i = read_job_answer(answer, jobs);
        progress.finished(i, jobs[i].status == "ran"       ? JobProgress::done
                             : jobs[i].status == "current" ? JobProgress::skipped
                                                           : JobProgress::failed);
      },
      [&](int i, int) { progress.started(i); });
  if (!root) return {};

  for (std::size_t j = 0; j < jobs.size(); ++j) jobs[j].seconds += member_seconds[j];
  StudyOutcome outcome;
  for (const Job& job : jobs) {
    outcome.ran += job.status == "ran";
    outcome.current += job.status == "current";
    outcome.failed += job.status == "failed";
  }
  write_tables(jobs, study, o.out);

  if (o.report && !stop_requested()) {
    event("report: analysis/report/report.py " + o.out.string());
    const std::string failed = run_report_script("report.py", o.out);
    outcome.report_written = failed.empty();
    if (!failed.empty()) event("report: FAILED: " + failed);
  }
  return outcome;
}

}  // namespace ishibashi
