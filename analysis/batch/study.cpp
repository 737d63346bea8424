#include "analysis/batch/study.h"

#include <chrono>
#include <cstdio>
#include <mutex>
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
void run_job(Job& job, int i, const StudyFile& study, const StudyOptions& o, int threads, const std::string& name,
             StudyProgress& progress, const std::function<void(const std::string&)>& event) {
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

  run_jobs(
      every_job(static_cast<int>(jobs.size())), workers, o.mpi,
      [&](int i) {
        run_job(jobs[i], i, study, o, threads, job_name(jobs[i]) + rank_here, progress, event);
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
