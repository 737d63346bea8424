// `ishibashi run scenario.toml`: settle the model under gravity, then shake it with the
// recorded ground motion, writing the ParaView series, history.csv and summary.json.
#pragma once
#include <filesystem>
#include <string>

#include "io/run_settings.h"

namespace ishibashi {

struct RunOptions {
  std::filesystem::path scenario;
  std::filesystem::path out;  // empty: out/<scenario name>
  bool profile = false;       // print the per-stage time table at the end (threads' work, waiting, imbalance)
  std::filesystem::path trace;     // non-empty: a Chrome trace-event timeline of trace_steps here
  std::string trace_steps = "1000:1100";  // FROM:TO, steps counted from the run's start
  bool quiet = false;         // no progress bar
  bool no_report = false;     // no report.png (analysis/report/run_report.py) at the end
  RunOverrides overrides;     // settings replacing the scenario's (--dt, --duration, ...; a resume: --threads)
  double dt_factor = 1;       // multiplies the time step (0.5: half of it, for convergence studies)
  bool fixed_threads = false; // every step on all threads (default: the team size found fastest)
  double checkpoint_every_s = 0;   // > 0: a checkpoint every this many simulated seconds
  double checkpoint_wall_s = 0;    // > 0: a checkpoint every this many wall-clock seconds
  std::filesystem::path resume;    // continue the run in this folder from its checkpoint
  int members = 0;                 // > 0: an ensemble of this many members (else the scenario's [ensemble] members)
  long seed = -1;                  // >= 0: the ensemble's seed, replacing the scenario's
  int jobs = 1;                    // ensemble or probe members at once
  std::string member_range;        // FROM:TO: run members FROM to TO - 1 only (empty: all)
  int probe_members = 0;           // > 0: a chaos probe of this many members (chaos_probe.h)
  double perturbation_m = 1e-6;    // the probe's move of each free stone
  double branch_at_s = -1;         // >= 0: the probe's branch, seconds of shaking
};

// Returns the exit code: 0 done, 130 interrupted (outputs valid up to that moment, and
// resumable when checkpoints were asked for).
int run_scenario(const RunOptions& options);

}  // namespace ishibashi
