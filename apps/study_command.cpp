#include "apps/study_command.h"

#include <cstdio>

#include "analysis/batch/study.h"
#include "analysis/model/program_files.h"
#include "analysis/run/seismic_run.h"

namespace ishibashi {

int run_study_command(const StudyCommandOptions& o) {
  const std::filesystem::path file = o.file.empty() ? program_file("scenarios/nishida_study.toml") : o.file;
  const StudyFile study = read_study(file, o.quick);
  const MpiSession mpi;  // under mpirun: the jobs handed out across the ranks
  StudyOptions options;
  options.mpi = &mpi;
  options.out = !o.out.empty() ? o.out : o.quick ? "out/study_quick" : "out/study";
  options.jobs = o.jobs;
  options.threads_per_job = o.threads_per_job;
  options.members = o.members;
  options.run_overrides = o.run_overrides;
  options.force = o.force;
  options.report = !o.no_report;
  options.on_event = [](const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  };
  stop_runs_on_interrupt();
  const StudyOutcome r = run_study(study, options);
  if (mpi.rank() != 0) return stop_requested() ? 1 : 0;
  std::printf("study: %d jobs ran, %d were current, %d failed%s\n", r.ran, r.current, r.failed,
              stop_requested() ? " (interrupted)" : "");
  if (r.report_written) std::printf("report: %s (and report.md, figures/)\n", (options.out / "report.html").c_str());
  return r.failed == 0 && !stop_requested() && (r.report_written || o.no_report) ? 0 : 1;
}

}  // namespace ishibashi
