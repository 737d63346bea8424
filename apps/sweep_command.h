// `ishibashi sweep FILE`: every (record, intensity) run of a sweep file, on this machine
// or, under mpirun, across machines; then the IDA curves and the fragility curve.
#pragma once
#include <filesystem>

namespace ishibashi {

struct SweepCommandOptions {
  std::filesystem::path file;
  std::filesystem::path out;  // empty: out/<sweep file name>
  int jobs = 1;               // runs at once on one machine (under mpirun: one per rank)
  int threads_per_job = 0;
  double checkpoint_wall_s = 300;  // each run's checkpoint (SweepOptions)
};

// 0 when every run is done and the curves written; 1 otherwise.
int run_sweep_command(const SweepCommandOptions& options);

}  // namespace ishibashi
