// A whole study in one call: the modal and impulse analysis of every model and every
// seismic run of a study file, several at once within a thread budget, skipping the jobs
// whose outputs are current (same inputs, same program), then the tables and the report.
//
// Layout of the output folder:
//   frequencies/<model>/   modes.csv, modes.vtu, spectrum_*.csv, peaks.csv, row.csv
//   runs/<scenario>/       blocks.pvd, contacts.pvd, history.csv, summary.json, ground_motion.csv, row.csv;
//                          with members: member_NNN/ (each member's run), ensemble.csv, ensemble.json,
//                          ground_motion.csv, row.csv
//   frequencies.csv, runs.csv (one row per job), jobs.csv (what ran, was current or failed)
//   report.md, report.html, figures/*.png (analysis/report/report.py)
#pragma once
#include <filesystem>
#include <functional>
#include <string>

#include "analysis/batch/mpi_ranks.h"
#include "io/run_settings.h"
#include "io/study_file.h"

namespace ishibashi {

struct StudyOptions {
  std::filesystem::path out;
  int jobs = 1;              // analyses at once
  int threads_per_job = 0;   // 0: the cores shared among the jobs
  int members = -1;          // >= 0: replaces the study file's members (each run an ensemble of them)
  RunOverrides run_overrides;  // every run's settings replaced by these (`study --damping implicit`)
  bool force = false;        // rerun jobs whose outputs are current
  bool report = true;        // write the report (python3 with matplotlib)
  std::function<void(const std::string&)> on_event;  // a job started, finished, was skipped or failed; progress
  double progress_every_s = 60;  // a progress line at most this often while runs advance
  const MpiSession* mpi = nullptr;  // under mpirun, more than one rank: the jobs handed out across them
};

struct StudyOutcome {
  int ran = 0, current = 0, failed = 0;
  bool report_written = false;
};

// Under mpirun every rank calls it: rank 0 hands out the jobs (one per rank at a time, each
// on its node's cores shared among the node's ranks), then writes the tables and the report;
// the other ranks' outcomes are empty.
StudyOutcome run_study(const StudyFile& study, const StudyOptions& options);

}  // namespace ishibashi
