// Parameter sweeps: every (record, intensity level) pair of a sweep file as a seismic run,
// on one machine (several runs at once) or across machines with MPI (one run per rank at
// a time, dynamic assignment: a rank that finishes takes the next run). Each finished run
// is a row of sweep.csv, appended as it finishes by one writer (rank 0), so a sweep that
// dies resumes where it stopped: runs with a row are never redone, and a run under way goes
// on from its last checkpoint.
//
// Outputs in the sweep's folder:
//   runs/<scenario>/<record>_<level>/  each run's series, history and summary
//   sweep.csv                scenario,record,level,scale_factor,pga_g,failed, then the run's
//                            result (run_result.h), and the host
//   ida.csv                  the IDA curves: per scenario and record, PGA against crown drop
//   fragility_fit.csv        per scenario, the fitted lognormal curve (median, beta)
//   fragility.csv            per scenario, the curve's points
//   comparison.csv           with several scenarios, each against the first: the cases
//                            (record, level) where one fails and the other stands, and the
//                            likelihood ratio of two fragility curves against one
//   ida.png, fragility.png   (analysis/report/sweep_plots.py, matplotlib)
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/batch/mpi_ranks.h"
#include "analysis/batch/sweep_table.h"
#include "io/sweep_file.h"

namespace ishibashi {

struct SweepOptions {
  std::filesystem::path out;
  int jobs = 1;             // runs at once on this machine (per MPI rank: 1)
  int threads_per_job = 0;  // 0: this node's cores shared among its runs
  double checkpoint_wall_s = 300;  // each run's checkpoint, so that a killed or interrupted sweep goes on from it
  std::function<void(const std::string&)> on_event;
};

struct SweepOutcome {
  int ran = 0, kept = 0, failed = 0;  // runs done now, rows kept from before, runs that threw
  std::vector<ScenarioFragility> fragility;  // per scenario, in the file's order (rank 0 only)
  bool plots_written = false;
};

// Every rank calls it; rank 0 assigns the runs, writes sweep.csv and the curves.
SweepOutcome run_sweep(const SweepFile& sweep, const SweepOptions& options, const MpiSession& mpi);

}  // namespace ishibashi
