#include "apps/sweep_command.h"

#include <cstdio>

#include "analysis/seismic_run.h"
#include "analysis/sweep.h"

namespace ishibashi {

int run_sweep_command(const SweepCommandOptions& o) {
  const MpiSession mpi;
  const SweepFile sweep = read_sweep(o.file);
  SweepOptions options;
  options.out = o.out.empty() ? std::filesystem::path("out") / o.file.stem() : o.out;
  options.jobs = o.jobs;
  options.threads_per_job = o.threads_per_job;
  options.on_event = [](const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  };
  stop_runs_on_interrupt();
  const SweepOutcome r = run_sweep(sweep, options, mpi);
  if (mpi.rank() != 0) return r.failed == 0 ? 0 : 1;
  const FragilityFit& f = r.fragility;
  std::printf("sweep: %d runs done now, %d done before, %d failed%s\n", r.ran, r.kept, r.failed,
              stop_requested() ? " (interrupted: run the same command again to go on)" : "");
  std::printf("fragility (lognormal, maximum likelihood, %d runs, %d failures): median PGA %.3f g, beta %.3f%s\n",
              f.outcomes, f.failures, f.median, f.beta,
              f.degenerate ? " (degenerate: all runs failed, none did, or failures and survivals do not overlap)" : "");
  std::printf("outputs in %s: sweep.csv, ida.csv, fragility.csv, fragility_fit.csv%s\n", options.out.c_str(),
              r.plots_written ? ", ida.png, fragility.png" : "");
  return r.failed == 0 && !stop_requested() ? 0 : 1;
}

}  // namespace ishibashi
