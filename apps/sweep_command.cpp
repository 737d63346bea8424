#include "apps/sweep_command.h"

#include <cstdio>

#include "analysis/batch/sweep.h"
#include "analysis/run/seismic_run.h"

namespace ishibashi {

int run_sweep_command(const SweepCommandOptions& o) {
  const MpiSession mpi;
  const SweepFile sweep = read_sweep(o.file);
  SweepOptions options;
  options.out = o.out.empty() ? std::filesystem::path("out") / o.file.stem() : o.out;
  options.jobs = o.jobs;
  options.threads_per_job = o.threads_per_job;
  options.checkpoint_wall_s = o.checkpoint_wall_s;
  options.on_event = [](const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  };
  stop_runs_on_interrupt();
  const SweepOutcome r = run_sweep(sweep, options, mpi);
  if (mpi.rank() != 0) return r.failed == 0 ? 0 : 1;
  std::printf("sweep: %d runs done now, %d done before, %d failed%s\n", r.ran, r.kept, r.failed,
              stop_requested() ? " (interrupted: run the same command again to go on)" : "");
  for (const ScenarioFragility& s : r.fragility) {
    const FragilityFit& f = s.fit;
    if (f.degenerate)
      std::printf("fragility of %s (%d runs, %d failures): no curve fits, %s\n", s.scenario.c_str(), f.outcomes, f.failures,
                  degenerate_reason(f, "g").c_str());
    else
      std::printf("fragility of %s (lognormal, maximum likelihood, %d runs, %d failures): median PGA %.3f g, beta %.3f\n",
                  s.scenario.c_str(), f.outcomes, f.failures, f.median, f.beta);
    if (s.reference.empty()) continue;
    std::printf("  against %s on the same %d cases (record, level, member): both stand %d, both fail %d, only %s fails %d, only %s fails %d; "
                "one curve for both: p = %.3g (likelihood ratio %.2f)\n",
                s.reference.c_str(), s.cases, s.both_stand, s.both_fail, s.reference.c_str(), s.only_reference_fails,
                s.scenario.c_str(), s.only_scenario_fails, s.against_reference.p_value, s.against_reference.statistic);
  }
  std::printf("outputs in %s: sweep.csv, ida.csv, fragility.csv, fragility_fit.csv%s%s\n", options.out.c_str(),
              sweep.scenarios.size() > 1 ? ", comparison.csv" : "",
              r.plots_written ? ", ida.png, fragility.png" : "");
  return r.failed == 0 && !stop_requested() ? 0 : 1;
}

}  // namespace ishibashi
