// The seismic run (MODEL.md section 6.2): settle the model under gravity, then shake it
// with a recorded three-component ground motion through its fixed blocks, recording the
// ParaView series (blocks.pvd, contacts.pvd), history.csv and summary.json as it goes.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "analysis/run/run_result.h"
#include "engine/joints.h"
#include "engine/world.h"
#include "io/ground_motion.h"
#include "io/scenario_file.h"

namespace ishibashi {

// The time step a scenario gets when it sets none, as a share of the stability limit.
// With the study's dashpots the limit is theirs. With implicit dashpots it is the springs'
// alone (backward Euler keeps every damped mode stable), and the step must also resolve
// the springs' stiffest oscillations: at 0.4 of that limit model A's first opening and
// fallen stones match the explicit run's (0.8 moved its mortar's first crack by 0.2 s;
// scenarios/results/README.md, "Implicit dashpots"). With capped
// dashpots it is the springs' alone too; at 0.3 of it the mode that sets a block's cap
// keeps a damping ratio of 1.15 ((1 - x^2) / 2x at x = 0.3 / 0.8, update_damping_caps),
// still overdamped, and a contact's stiffest oscillation gets about 10 steps. 0.4 changed model A's outcome over 5 s of
// Kobe (scenarios/results/README.md, "Capped dashpots").
constexpr double kStudyDtShare = 0.8;
constexpr double kImplicitDtShare = 0.4;
constexpr double kCappedDtShare = 0.3;
// Settling ends at the first check of the kinetic energy (this often) below the
// scenario's settle_kinetic_j: 0.05 s, the presets' output interval, as before it was fixed.
constexpr double kSettleCheckS = 0.05;

struct SeismicRunOptions {
  std::filesystem::path out;  // output folder (created)
  double dt_factor = 1;       // multiplies the time step (0.5 halves it: convergence studies)
  bool adaptive_threads = true;  // false: every step on all the scenario's threads (World)
  // Checkpoints (checkpoint.bin in `out`, replaced atomically at an output frame) every
  // this many simulated seconds and/or wall-clock seconds; 0: none. A run stopped by a
  // signal writes one too, when either is set.
  double checkpoint_every_s = 0;
  double checkpoint_wall_s = 0;
  // Time each thread's share of every stage (run --profile: work, waiting, imbalance), and
  // keep a timeline of steps [trace_first_step, trace_last_step) (run --trace), counted
  // from the run's start, settling included.
  bool time_threads = false;
  // >= 0: this run is member `member` of the scenario's [ensemble] (ensemble.h): its free
  // stones' poses, joints' friction and record's amplitude as the member draws them.
  int member = -1;
  long trace_first_step = 0, trace_last_step = 0;
  // >= 0: the run stops at the first output frame after this many seconds of shaking and
  // writes its checkpoint there (the chaos probe's branch point, chaos_probe.h).
  double branch_at_shake_s = -1;
  // Called with the state read from a checkpoint, before the run goes on from it (the
  // chaos probe perturbs its members there).
  std::function<void(const Model&, State&)> on_resume;
  // Called after every output frame of the shaking with the result so far: true ends the
  // run there, finished, its summary saying so ("stopped_early"): a sweep's failure
  // criteria once its verdict is decided ([failure] stop_at_failure). A scenario's
  // [run] stop_at = "collapse" does the same at its collapse.
  std::function<bool(const SeismicRunResult&)> stop_when;
  // Called after every output frame of the shaking with the state and the fraction done (0..1).
  std::function<void(const State&, double fraction_done)> on_frame;
  // Called after every output frame of the settling (minutes of a large bridge before the
  // shaking's first frame) with the state; the time is s.time_s of at most settle_max_s,
  // and the settling ends when the kinetic energy falls below settled_below_j.
  std::function<void(const State&, double settle_max_s, double settled_below_j)> on_settle_frame;
  // Warnings worth a user's attention (a block that left the model).
  std::function<void(const std::string&)> on_warning;
};

// Stops every run in this process at its next step (from a signal handler too).
void request_stop();
bool stop_requested();
// SIGINT, SIGTERM and SIGHUP (unless ignored, as nohup does) call request_stop.
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
  // `overrides` may change how it runs, not what (the command line allows threads alone).
  // `checkpoint`: another run's checkpoint to go on from instead (the chaos probe's
  // members from its branch), into options.out. `started_as`: the scenario as its caller
  // built the run from the file (a sweep's case: its record, scaled), instead of the file as
  // written; the checkpoint's settings replace its own.
  static std::unique_ptr<SeismicRun> resume(SeismicRunOptions options, const RunOverrides& overrides = {},
                                            const std::filesystem::path& checkpoint = {},
                                            const Scenario* started_as = nullptr);

  const Scenario& scenario() const { return scenario_; }
  const World& world() const { return *world_; }
  double dt_s() const { return dt_; }
  double stability_limit_s() const { return limit_s_; }
  int limiting_block() const { return limiting_block_; }
  const GroundMotionStream& ground_motion() const { return ground_; }
  // The shaking's peaks by component (a member's amplitude draw included).
  const GroundMotionPeaks& ground_motion_peaks() const { return peaks_; }
  int monitored_block() const { return monitors_.empty() ? -1 : monitors_.front(); }
  // Where this process took the run up: the checkpoint's step and profile (0 and empty for
  // a new run), so that run --profile reports the steps it ran itself.
  long first_step() const { return first_step_; }
  const Profile& profile_at_first_step() const { return profile_at_first_step_; }

  // Settles, then shakes; returns when the ground motion ends or a stop is requested.
  SeismicRunResult run();

 private:
  struct Progress;  // what run() carries from step to step beside the World (seismic_run.cpp)
  void settle(Progress& p);
  void shake(Progress& p);
  void maybe_checkpoint(Progress& p);  // when the options' interval has passed
  void write_checkpoint(Progress& p);
  void restore_checkpoint(Progress& p);
  void write_summary(Progress& p, bool finished);

  Scenario scenario_;
  SeismicRunOptions options_;
  double limit_s_ = 0, dt_ = 0;
  long steps_per_frame_ = 1;  // steps between output frames
  int limiting_block_ = -1;
  GroundMotionStream ground_;
  GroundMotionPeaks peaks_;
  std::unique_ptr<World> world_;
  std::vector<int> monitors_;
  std::string resume_from_;  // the checkpoint's body (after its header); empty: a new run
  long first_step_ = 0;
  Profile profile_at_first_step_;
};

// The fraction of the energy exchanged (the ground's work, dashpots, friction and broken
// bonds) that the balance misses.
double relative_balance_error(const Energy& energy);

}  // namespace ishibashi
