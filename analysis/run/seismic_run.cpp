#include "analysis/run/seismic_run.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <sstream>

#include "analysis/model/compile_model.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/checkpoint.h"
#include "analysis/run/member_draw.h"
#include "analysis/run/run_recorder.h"
#include "engine/cores.h"
#include "geometry/bridge.h"
#include "io/folder_lock.h"

namespace ishibashi {
namespace {

std::atomic<int> stop_flag{0};  // lock-free: safe to set from a signal handler
extern "C" void on_interrupt(int) { stop_flag = 1; }

using Clock = std::chrono::steady_clock;

}  // namespace

void request_stop() { stop_flag = 1; }
bool stop_requested() { return stop_flag != 0; }
void stop_runs_on_interrupt() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  // A closed terminal (a dropped ssh session) stops the run as Ctrl-C does, with its
  // summary and checkpoint, where it killed it between frames; under nohup it stays ignored.
  if (std::signal(SIGHUP, on_interrupt) == SIG_IGN) std::signal(SIGHUP, SIG_IGN);
}

double relative_balance_error(const Energy& e) {
  return e.exchanged_j() > 0 ? e.balance_error_j() / e.exchanged_j() : 0.0;
}

SeismicRun::SeismicRun(const Scenario& scenario, SeismicRunOptions options)
    : scenario_(scenario), options_(std::move(options)) {
  const RunSettings& settings = scenario_.settings;
  if (std::none_of(scenario_.ground_motion.component.begin(), scenario_.ground_motion.component.end(),
                   [](const auto& c) { return c.has_value(); }))  // before the model's minutes of building
    throw InputError(scenario_.file.string() + ": no ground motion to shake with: [ground_motion] x, y or z = { file = ... }");
  // Threads of this run: the calling thread's OpenMP teams (a study runs several at once).
  use_threads(settings.threads);
  ModelOptions model_wanted = model_options(settings);
  model_wanted.drive_fixed_blocks = true;  // the fixed blocks move with the ground (kinematic drive)
  Model model = load_model(scenario_.model, scenario_.model_file, model_wanted);
  GroundMotionSpec motion = scenario_.motion();
  if (options_.member >= 0) {
    const MemberDraw draw = draw_member(scenario_.ensemble, options_.member);
    perturb_model(model, scenario_.ensemble, draw);
    for (auto& component : motion.component)
      if (component) component->scale *= draw.amplitude;
  }
  limit_s_ = World(model, 1e-9).critical_time_step_s(&limiting_block_);
  if (limiting_block_ < 0 && !(settings.dt_s > 0))
    throw InputError(scenario_.file.string() + ": no two blocks of its model " +
                     "touch at the start, so no contact sets the time step; set dt_s in [run] (or --dt)");
  const double share = settings.damping == Damping::capped     ? kCappedDtShare
                       : settings.damping == Damping::implicit ? kImplicitDtShare
                                                               : kStudyDtShare;
  dt_ = (settings.dt_s > 0 ? settings.dt_s : share * limit_s_) * options_.dt_factor;
  steps_per_frame_ = std::max(1L, std::lround(settings.output_interval_s / dt_));
  ground_ = GroundMotionStream(motion, dt_);
  peaks_ = ishibashi::ground_motion_peaks(motion);
  world_ = std::make_unique<World>(model, dt_);
  world_->set_adaptive_threads(options_.adaptive_threads);
  world_->set_thread_timing(options_.time_threads);
  if (options_.trace_last_step > options_.trace_first_step)
    world_->trace_steps(options_.trace_first_step, options_.trace_last_step);
  const Model& m = world_->model();
  monitors_ = scenario_.monitor_blocks;
  if (monitors_.empty() && crown_unit(m) >= 0) monitors_.push_back(crown_unit(m));
  for (int b : monitors_)
    if (b < 0 || b >= m.block_count)
      throw InputError(scenario_.file.string() + ": [monitor] block " + std::to_string(b) + " does not exist (the model has " +
                       std::to_string(m.block_count) + " blocks, 0 to " + std::to_string(m.block_count - 1) + ")");
}

SeismicRun::~SeismicRun() = default;

std::unique_ptr<SeismicRun> SeismicRun::resume(SeismicRunOptions options, const RunOverrides& overrides,
                                               const std::filesystem::path& checkpoint, const Scenario* started_as) {
  const std::filesystem::path file = checkpoint.empty() ? options.out / "checkpoint.bin" : checkpoint;
  std::string body;
  const CheckpointHeader h = read_checkpoint_file(file, &body);
  // ISHIBASHI_RESUME_ANY_BUILD (benchmarks only: perf/late_phase_ab.sh) lets two builds
  // go on from one state; the run is then not bit-identical to an unbroken one.
  if (h.program != program_fingerprint() && !std::getenv("ISHIBASHI_RESUME_ANY_BUILD"))
    throw InputError(file.string() + ": written by another build of ishibashi; resume it with that build, or start the run again");
  if (!std::filesystem::exists(h.scenario_file))
    throw InputError(file.string() + ": its scenario " + h.scenario_file + " no longer exists");
  if (h.inputs != scenario_fingerprint(h.scenario_file))
    throw InputError(file.string() + ": the scenario " + h.scenario_file +
                     ", its model file or its records changed since the checkpoint was written; start the run again");
  Scenario sc = started_as ? *started_as : read_scenario(h.scenario_file);
  sc.settings = h.settings;
  apply_overrides(sc.settings, overrides);
  options.dt_factor = 1;  // h.dt_s is the step the run used
  options.member = h.member;
  auto run = std::make_unique<SeismicRun>(sc, std::move(options));
  run->resume_from_ = std::move(body);
  return run;
}

// What run() carries from step to step beside the World: the joints, the outputs so far and
// where the run is. visit() lists what a checkpoint holds of it, for writing and reading.
struct SeismicRun::Progress {
  Progress(const SeismicRunOptions& options, const Model& m, const std::vector<int>& monitors, const State& s)
      : joints(find_original_joints(s, soil_blocks(m))), recorder(options.out, m, joints, monitors, options.on_warning) {}
  // The masonry's joints: a soil fill's elements part and slide as soil does.
  static std::vector<std::uint8_t> soil_blocks(const Model& m) {
    std::vector<std::uint8_t> soil(m.block_count, 0);
    for (int b = 0; b < m.block_count; ++b) soil[b] = m.block_tag[b].part == static_cast<int>(Part::soil);
    return soil;
  }

  Joints joints;
  RunRecorder recorder;
  SeismicRunResult result;
  bool shaking = false;  // settled: the ground moves
  bool branched = false;  // stopped at options.branch_at_shake_s
  long shake_step = 0;   // the next step of the ground motion
  Vec3 settled_crown = Vec3::Zero();
  Vec3 ground_accel = Vec3::Zero(), ground_displacement = Vec3::Zero();  // at the last step
  Clock::time_point wall0 = Clock::now(), checkpoint_wall = Clock::now();
  double wall_before_s = 0;  // of the earlier parts of a resumed run, each to its last checkpoint
  double checkpoint_time_s = 0;
  // The bond utilisation's largest sample since the last frame (every 50 steps of shaking,
  // while bonds are left); -1: none.
  double utilisation_since_frame = -1;
  bool bonds_left = true;
  double wall_s() const { return wall_before_s + std::chrono::duration<double>(Clock::now() - wall0).count(); }

  template <class Archive>
  void visit(Archive& a) {
    a.field(shaking), a.field(shake_step), a.field(utilisation_since_frame), a.field(bonds_left);
    result.for_each_field([&](auto& field) { a.field(field); });
    for (int i = 0; i < 3; ++i) a.field(settled_crown[i]);
    recorder.visit(a);
    visit_joints(a, joints);
  }
  // Records a frame and takes its counts into the result.
  void record(const char* phase, const Model& m, const State& s) {
    const Clock::time_point start = Clock::now();
    const RunCounts c = recorder.record(phase, s, ground_accel, ground_displacement, joints, utilisation_since_frame);
    utilisation_since_frame = -1;
    result.output_wall_s += std::chrono::duration<double>(Clock::now() - start).count();
    take_counts(m, c, result);
  }
};

void SeismicRun::write_summary(Progress& p, bool finished) {
  const State& s = world_->state();
  SeismicRunResult& r = p.result;
  const Energy& e = s.energy;
  r.shaking_time_s = p.shaking ? s.time_s - r.settle_time_s : 0;  // none while settling
  r.balance_error_j = e.balance_error_j();
  r.balance_error_relative = relative_balance_error(e);
  r.reclip_j = e.reclip_j, r.reclip_relative = e.exchanged_j() > 0 ? e.reclip_j / e.exchanged_j() : 0.0;
  r.steps = s.step;
  r.state_hash = world_->state_hash();
  r.motion_hash = world_->motion_hash();
  r.wall_s = p.wall_s();
  const BridgeSpec& bridge = scenario_.model.bridge;
  RunDescription run{scenario_.model.name, monitored_block(), dt_, world_->thread_tuner().max_threads(), bridge.mortar_pa,
                     {bridge.mortar_tension_fracture_j_m2, bridge.mortar_shear_fracture_j_m2}, mortar_part_names(bridge),
                     scenario_.settings, peaks_, {}};
  if (options_.member >= 0) run.member = {options_.member, draw_member(scenario_.ensemble, options_.member), scenario_.ensemble};
  p.recorder.write_summary(run, r, s, p.joints, finished);
}

// Everything the rest of the run depends on, at an output frame (CheckpointWriter).
void SeismicRun::write_checkpoint(Progress& p) {
  const State& s = world_->state();
  CheckpointHeader h{program_fingerprint(), scenario_fingerprint(scenario_.file),
                     std::filesystem::absolute(scenario_.file).string(), scenario_.settings, options_.member};
  h.settings.dt_s = dt_;  // the step used (dt_factor applied)
  p.result.wall_s = p.wall_s();  // the work so far, what a resumed run's wall time goes on from
  std::ostringstream body;
  CheckpointWriter w(body);
  p.visit(w);
  write_state(w, s);
  write_checkpoint_file(options_.out / "checkpoint.bin", h, body.str());
  p.checkpoint_time_s = s.time_s;
  p.checkpoint_wall = Clock::now();
}

void SeismicRun::restore_checkpoint(Progress& p) {
  const std::filesystem::path file = options_.out / "checkpoint.bin";
  State& s = world_->state();
  std::istringstream body(resume_from_);
  CheckpointReader in(body);
  try {
    const Joints found = p.joints;
    p.visit(in);
    check_joints_fit(p.joints, found);
    read_state(in, s);
    check_state_fits(s, world_->model());
    p.wall_before_s = p.result.wall_s;
    first_step_ = s.step;
    profile_at_first_step_ = s.profile;
  } catch (const CheckpointError& e) {
    throw InputError(file.string() + ": damaged checkpoint (" + e.what() + ")");
  }
  p.checkpoint_time_s = s.time_s;
}

// Under gravity until the kinetic energy is negligible; then mortar sets (when it sets in
// the settled pose), the joints' reference is the settled pose, and the ground starts to move.
void SeismicRun::settle(Progress& p) {
  World& world = *world_;
  const Model& m = world.model();
  State& s = world.state();
  const double settle_max_s = scenario_.settings.settle_max_s;
  if (s.step == 0) {
    p.record("settle", m, s);
    p.recorder.refuse_frames_the_disk_cannot_hold(ground_.steps() / steps_per_frame_ + 1, steps_per_frame_ * dt_);
  }
  // Rest is judged every kSettleCheckS whatever the output interval, so that finer frames
  // do not end the settling elsewhere; a frame is written at the end of it too.
  const long check_steps = std::max(1L, std::lround(kSettleCheckS / dt_));
  while (!stop_requested() && s.time_s < settle_max_s) {
    const long to_frame = steps_per_frame_ - s.step % steps_per_frame_, to_check = check_steps - s.step % check_steps;
    const long to_end = std::lround((settle_max_s - s.time_s) / dt_) + 1;
    // At most 500 steps between looks at a stop request: a check is 0.05 s of settling, ten
    // thousand explicit steps or minutes of a large bridge, too long to wait on Ctrl-C.
    const long steps = std::min({to_frame, to_check, to_end, 500L});
    world.run(steps);
    const bool last = steps == to_end;  // settle_max_s reached: a frame and a check
    const bool frame = last || s.step % steps_per_frame_ == 0;
    if ((last || s.step % check_steps == 0) && s.energy.kinetic_j < scenario_.settings.settle_kinetic_j) {
      p.result.settled = true;
      p.record("settle", m, s);
      break;
    }
    if (frame) {
      p.record("settle", m, s);
      if (options_.on_settle_frame) options_.on_settle_frame(s, settle_max_s, scenario_.settings.settle_kinetic_j);
      maybe_checkpoint(p);
    }
  }
  if (stop_requested()) return;
  p.result.settle_time_s = s.time_s;
  if (m.options.bonds_when_settled) world.form_bonds();
  p.result.bonds_broken_settling = set_joint_reference(s, p.joints);  // cracks of the shaking, from the settled pose
  if (monitored_block() >= 0) p.settled_crown = s.position[monitored_block()];
  p.shaking = true;
  write_summary(p, false);
}

// The prescribed blocks move with the ground, one step of the record at a time.
void SeismicRun::shake(Progress& p) {
  World& world = *world_;
  const Model& m = world.model();
  State& s = world.state();
  SeismicRunResult& r = p.result;
  GroundMotionStream& ground = ground_;
  const long n = ground.steps();
  const int crown = monitored_block();
  if (ground.step() != p.shake_step) ground.rewind_to(p.shake_step);  // a resumed run
  if (p.shake_step > 0) p.ground_accel = ground.accel_m_s2(), p.ground_displacement = ground.displacement_m();
  const JointThresholds thresholds;
  for (long k = p.shake_step; p.shaking && k < n && !stop_requested(); ++k) {
    const Vec3 velocity_before = ground.velocity_m_s();
    ground.advance();
    const Vec3 v = 0.5 * (velocity_before + ground.velocity_m_s());  // exact displacement per step
    for (int b = 0; b < m.block_count; ++b)
      if (m.motion[b] == Motion::prescribed) s.velocity[b] = v;
    world.step();
    p.ground_accel = ground.accel_m_s2();
    p.ground_displacement = ground.displacement_m();
    // Every 50 steps (0.2-2 ms, a small part of a pulse): how close the mortar came to
    // cracking, for the next frame's row, and until the first crack whether a joint cracked.
    if ((k + 1) % 50 == 0 && (p.bonds_left || r.first_opening_s < 0)) {
      double utilisation;
      if (r.first_opening_s < 0) {
        const RunCounts c = count_damage(m, s, thresholds, p.joints);
        utilisation = c.bond_utilisation;
        r.bond_utilisation_peak = std::max(r.bond_utilisation_peak, utilisation);
        if (c.joints.cracked > 0) r.first_opening_s = s.time_s - r.settle_time_s;
      } else {
        utilisation = largest_bond_utilisation(m, s);
      }
      p.utilisation_since_frame = std::max(p.utilisation_since_frame, utilisation);
      p.bonds_left = utilisation >= 0;  // a broken bond never forms again while shaking
    }
    if (crown >= 0)  // the crown's drop relative to the ground since settling
      r.largest_crown_drop_m =
          std::max(r.largest_crown_drop_m, p.settled_crown.z() - s.position[crown].z() + p.ground_displacement.z());
    p.shake_step = k + 1;
    if ((k + 1) % steps_per_frame_ != 0 && k + 1 < n) continue;  // no output frame
    p.record("shake", m, s);
    write_summary(p, false);
    if (options_.on_frame) options_.on_frame(s, double(k + 1) / n);
    if (k + 1 == n) return;  // the record's end: nothing to branch, stop or checkpoint at
    if (options_.branch_at_shake_s >= 0 && s.time_s - r.settle_time_s >= options_.branch_at_shake_s - 0.5 * dt_) {
      write_checkpoint(p);  // the branch point, where the chaos probe's members go on from
      p.branched = true;
      return;
    }
    if ((options_.stop_when && options_.stop_when(r)) || (scenario_.settings.stop_at == StopAt::collapse && r.collapse)) {
      r.stopped_early = true;
      return;
    }
    maybe_checkpoint(p);
  }
}

void SeismicRun::maybe_checkpoint(Progress& p) {
  const double every = options_.checkpoint_every_s, wall_every = options_.checkpoint_wall_s;
  const double wall = std::chrono::duration<double>(Clock::now() - p.checkpoint_wall).count();
  if ((every > 0 && world_->state().time_s - p.checkpoint_time_s >= every - 0.5 * dt_) || (wall_every > 0 && wall >= wall_every))
    write_checkpoint(p);
}

SeismicRunResult SeismicRun::run() {
  const std::filesystem::path& out = options_.out;
  std::filesystem::create_directories(out);
  const FolderLock claim(out);
  std::filesystem::remove(out / "report.png");  // an earlier run's picture (`run` draws this one's at its end)
  if (!scenario_.file.empty() && std::filesystem::exists(scenario_.file))
    std::filesystem::copy_file(scenario_.file, out / "scenario.toml", std::filesystem::copy_options::overwrite_existing);
  Progress p(options_, world_->model(), monitors_, world_->state());
  p.result.joints = p.joints.size();
  p.checkpoint_time_s = world_->state().time_s;
  if (!resume_from_.empty()) restore_checkpoint(p);
  if (!resume_from_.empty() && options_.on_resume) options_.on_resume(world_->model(), world_->state());

  if (!p.shaking) settle(p);
  shake(p);

  p.result.interrupted = stop_requested() || p.branched;
  if (stop_requested()) {
    if (options_.checkpoint_every_s > 0 || options_.checkpoint_wall_s > 0)
      write_checkpoint(p);  // before the extra frame: the resumed run writes its own
    p.record("interrupted", world_->model(), world_->state());
  }
  write_summary(p, !p.result.interrupted);
  return p.result;
}

}  // namespace ishibashi
