// The seismic run (MODEL.md section 6.2): settle the model under gravity, then shake it
// with a recorded three-component ground motion through its fixed blocks, recording the
// ParaView series (blocks.pvd, contacts.pvd), history.csv and summary.json as it goes.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "engine/joints.h"
#include "engine/world.h"
#include "io/ground_motion.h"
#include "io/scenario_file.h"

namespace ishibashi {

// The time step a scenario gets when it sets none, as a share of the stability limit.
// With the study's dashpots the limit is theirs. With capped dashpots it is the springs'
// alone; at 0.3 of it the mode that sets a block's cap keeps a damping ratio of 1.15
// ((1 - x^2) / 2x at x = 0.3 / 0.8, update_damping_caps), still overdamped, and a contact's
// stiffest oscillation gets about 10 steps. 0.4 changed model A's outcome over 5 s of
// Kobe (scenarios/results/README.md, "Capped dashpots").
constexpr double kStudyDtShare = 0.8;
constexpr double kCappedDtShare = 0.3;

struct SeismicRunOptions {
  std::filesystem::path out;  // output folder (created)
  double dt_factor = 1;       // multiplies the time step (0.5 halves it: convergence studies)
  bool adaptive_threads = true;  // false: every step on all the scenario's threads (World)
  // Checkpoints (checkpoint.bin in `out`, replaced atomically at an output frame) every
  // this many simulated seconds and/or wall-clock seconds; 0: none. A run stopped by a
  // signal writes one too, when either is set.
  double checkpoint_every_s = 0;
  double checkpoint_wall_s = 0;
  // Called after every output frame of the shaking with the fraction done (0..1).
  std::function<void(double fraction_done)> on_frame;
  // Warnings worth a user's attention (a block that left the model).
  std::function<void(const std::string&)> on_warning;
};

// What a run found; also written to summary.json. (A new field also goes into
// for_each_field in seismic_run.cpp, which writes it to the checkpoint.)
struct SeismicRunResult {
  bool settled = false;           // the kinetic energy fell below the scenario's threshold
  bool interrupted = false;       // stopped by SIGINT/SIGTERM (outputs valid up to then)
  double settle_time_s = 0;
  double shaking_time_s = 0;      // simulated after settling
  double first_opening_s = -1;    // seconds of shaking until the first crack; -1: none
  double largest_crown_drop_m = 0;  // of the monitored block, relative to the ground
  int fallen_stones = 0, fallen_ring_stones = 0, blocks_left_model = 0;
  bool collapse = false;          // a ring stone fell, or more than 5 % of the blocks
  int joints = 0, bonds_broken_settling = 0;
  JointCounts joint_counts;       // at the end
  double balance_error_j = 0;
  double balance_error_relative = 0;  // of the energy exchanged
  long steps = 0;
  std::uint64_t state_hash = 0;
  double wall_s = 0;
};

// Stops every run in this process at its next step (from a signal handler too).
void request_stop();
bool stop_requested();
// SIGINT and SIGTERM call request_stop.
void stop_runs_on_interrupt();

class SeismicRun {
 public:
  // Loads and validates the model, builds the World at the scenario's time step and
  // prepares the ground motion. Throws InputError for bad input.
  SeismicRun(const Scenario& scenario, SeismicRunOptions options);
  ~SeismicRun();

  // The run whose checkpoint is options.out / "checkpoint.bin", ready to continue where
  // it was written: run() then appends to its series and history and ends bit-identical
  // to a run never stopped. Throws InputError when there is no checkpoint, or when it was
  // written by another build of the program or for other input files.
  static std::unique_ptr<SeismicRun> resume(SeismicRunOptions options);

  const Scenario& scenario() const { return scenario_; }
  const World& world() const { return *world_; }
  double dt_s() const { return dt_; }
  double stability_limit_s() const { return limit_s_; }
  int limiting_block() const { return limiting_block_; }
  const GroundMotion& ground_motion() const { return ground_; }
  int monitored_block() const { return monitors_.empty() ? -1 : monitors_.front(); }

  // Settles, then shakes; returns when the ground motion ends or a stop is requested.
  SeismicRunResult run();

 private:
  Scenario scenario_;
  SeismicRunOptions options_;
  double limit_s_ = 0, dt_ = 0;
  int limiting_block_ = -1;
  GroundMotion ground_;
  std::unique_ptr<World> world_;
  std::vector<int> monitors_;
  std::string resume_from_;  // the checkpoint's body (after its header); empty: a new run
};

// The fraction of the energy exchanged (the ground's work, dashpots, friction and broken
// bonds) that the balance misses.
double relative_balance_error(const Energy& energy);

}  // namespace ishibashi
