// `ishibashi run scenario.toml`: settle the model under gravity, then shake it with the
// recorded ground motion, writing the ParaView series, history.csv and summary.json.
#pragma once
#include <filesystem>
#include <string>

namespace ishibashi {

struct RunOptions {
  std::filesystem::path scenario;
  std::filesystem::path out;  // empty: out/<scenario name>
  bool profile = false;       // print the per-stage time table at the end
  bool quiet = false;         // no progress bar
  double duration_s = -1;     // >= 0: replaces the scenario's [run] duration_s (0: whole record)
  int threads = -1;           // >= 0: replaces the scenario's [run] threads (0: all cores)
  double start_s = -1;        // >= 0: replaces the scenario's [ground_motion] start_s
  double dt_s = -1;           // >= 0: replaces the scenario's [run] dt_s (0: 0.8 of the limit)
  double dt_factor = 1;       // multiplies the time step (0.5: half of it, for convergence studies)
  int subdivision = 0;        // > 0: replaces the scenario's [run] subdivision
  std::string joint_rule;     // non-empty: replaces the scenario's [run] joint_rule ("corners", "moments")
  std::string damping;        // non-empty: replaces the scenario's [run] damping ("study", "capped")
  bool fixed_threads = false; // every step on all threads (default: the team size found fastest)
  double checkpoint_every_s = 0;   // > 0: a checkpoint every this many simulated seconds
  double checkpoint_wall_s = 0;    // > 0: a checkpoint every this many wall-clock seconds
  std::filesystem::path resume;    // continue the run in this folder from its checkpoint
};

// Returns the exit code: 0 done, 130 interrupted (outputs valid up to that moment, and
// resumable when checkpoints were asked for).
int run_scenario(const RunOptions& options);

}  // namespace ishibashi
