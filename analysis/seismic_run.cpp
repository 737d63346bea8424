#include "analysis/seismic_run.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <sstream>

#include "analysis/fingerprint.h"
#include "analysis/load.h"
#include "engine/checkpoint.h"
#include "engine/parallel.h"
#include "geometry/bridge.h"
#include "io/atomic_file.h"
#include "io/vtk_output.h"

namespace ishibashi {
namespace {

std::atomic<int> stop_flag{0};  // lock-free: safe to set from a signal handler
extern "C" void on_interrupt(int) { stop_flag = 1; }

using Clock = std::chrono::steady_clock;

struct Counts {
  JointCounts joints;
  int fallen = 0, fallen_ring = 0;
  int left_model = 0;  // blocks that fell past the ground and were frozen there
};

Counts count(const Model& m, const State& s, const JointThresholds& thresholds, Joints& joints) {
  Counts c;
  c.joints = measure_joints(s, thresholds, joints);
  for (int b = 0; b < m.block_count; ++b) {
    c.left_model += s.left_model[b];
    if (is_fallen(m, s, b)) {
      ++c.fallen;
      c.fallen_ring += m.block_tag[b].part == static_cast<int>(Part::ring);
    }
  }
  return c;
}

constexpr char kCheckpointMagic[] = "ishibashi checkpoint 3\n";

// What the checkpoint's run was: the program, the input files and the run's settings
// beyond the scenario file (command-line overrides), so that a resume rebuilds the same run.
struct CheckpointHeader {
  std::uint64_t program = 0, inputs = 0;
  std::string scenario_file;
  double dt_s = 0, duration_s = 0, motion_duration_s = 0, start_s = 0;
  int subdivision = 1;
  bool cap_damping = false;
};

void write_header(CheckpointWriter& out, const CheckpointHeader& h) {
  out.text(kCheckpointMagic);
  out.value(h.program), out.value(h.inputs);
  out.text(h.scenario_file);
  out.value(h.dt_s), out.value(h.duration_s), out.value(h.motion_duration_s), out.value(h.start_s), out.value(h.subdivision);
  out.flag(h.cap_damping);
}

CheckpointHeader read_header(CheckpointReader& in, const std::filesystem::path& file) {
  if (in.text() != kCheckpointMagic) throw InputError(file.string() + ": not a checkpoint of this program");
  CheckpointHeader h;
  h.program = in.value<std::uint64_t>();
  h.inputs = in.value<std::uint64_t>();
  h.scenario_file = in.text();
  h.dt_s = in.value<double>(), h.duration_s = in.value<double>(), h.motion_duration_s = in.value<double>();
  h.start_s = in.value<double>(), h.subdivision = in.value<int>();
  h.cap_damping = in.flag();
  return h;
}

// Every field of a result, for the checkpoint: written one by one, flags as checked bytes.
template <class Result, class Fn>
void for_each_field(Result& r, Fn&& fn) {
  fn(r.settled), fn(r.interrupted), fn(r.settle_time_s), fn(r.shaking_time_s), fn(r.first_opening_s);
  fn(r.largest_crown_drop_m), fn(r.fallen_stones), fn(r.fallen_ring_stones), fn(r.blocks_left_model);
  fn(r.collapse), fn(r.joints), fn(r.bonds_broken_settling), fn(r.joint_counts), fn(r.balance_error_j);
  fn(r.balance_error_relative), fn(r.steps), fn(r.state_hash), fn(r.wall_s);
}

void write_result(CheckpointWriter& out, const SeismicRunResult& r) {
  for_each_field(r, [&](const auto& v) {
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, bool>) out.flag(v);
    else out.value(v);
  });
}

void read_result(CheckpointReader& in, SeismicRunResult& r) {
  for_each_field(r, [&](auto& v) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, bool>) v = in.flag();
    else v = in.value<T>();
  });
}

}  // namespace

void request_stop() { stop_flag = 1; }
bool stop_requested() { return stop_flag != 0; }
void stop_runs_on_interrupt() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

double relative_balance_error(const Energy& e) {
  const double exchanged = std::abs(e.prescribed_work_j) + std::abs(e.damping_j) + std::abs(e.friction_j) + std::abs(e.bond_j);
  return exchanged > 0 ? e.balance_error_j() / exchanged : 0.0;
}

SeismicRun::SeismicRun(const Scenario& scenario, SeismicRunOptions options)
    : scenario_(scenario), options_(std::move(options)) {
  // Threads of this run: the calling thread's OpenMP teams (a study runs several at once).
  if (scenario_.threads > 0) omp_set_num_threads(scenario_.threads);
  // The fixed blocks move with the ground (kinematic drive).
  Model model = load_model(scenario_.model, scenario_.model_file);
  model.contact.subdivision = scenario_.subdivision;
  model.contact.cap_damping = scenario_.cap_damping;
  for (Motion& motion : model.motion)
    if (motion == Motion::fixed) motion = Motion::prescribed;
  limit_s_ = World(model, 1e-9).critical_time_step_s(&limiting_block_);
  const double share = scenario_.cap_damping ? kCappedDtShare : kStudyDtShare;
  dt_ = (scenario_.dt_s > 0 ? scenario_.dt_s : share * limit_s_) * options_.dt_factor;
  ground_ = prepare_ground_motion(scenario_.ground_motion, dt_);
  world_ = std::make_unique<World>(model, dt_);
  world_->set_adaptive_threads(options_.adaptive_threads);
  const Model& m = world_->model();
  monitors_ = scenario_.monitor_blocks;
  if (monitors_.empty() && crown_unit(m) >= 0) monitors_.push_back(crown_unit(m));
  for (int b : monitors_)
    if (b < 0 || b >= m.block_count)
      throw InputError(scenario_.file.string() + ": [monitor] block " + std::to_string(b) + " does not exist (the model has " +
                       std::to_string(m.block_count) + " blocks, 0 to " + std::to_string(m.block_count - 1) + ")");
}

SeismicRun::~SeismicRun() = default;

std::unique_ptr<SeismicRun> SeismicRun::resume(SeismicRunOptions options) {
  const std::filesystem::path file = options.out / "checkpoint.bin";
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": no checkpoint to resume from (run with --checkpoint-every or --checkpoint-wall)");
  CheckpointHeader h;
  std::string body;
  try {
    CheckpointReader reader(in);
    h = read_header(reader, file);
    body.assign(std::istreambuf_iterator<char>(in), {});
  } catch (const CheckpointError& e) {
    throw InputError(file.string() + ": damaged checkpoint (" + e.what() + ")");
  }
  if (h.program != program_fingerprint())
    throw InputError(file.string() + ": written by another build of ishibashi; resume it with that build, or start the run again");
  if (!std::filesystem::exists(h.scenario_file))
    throw InputError(file.string() + ": its scenario " + h.scenario_file + " no longer exists");
  if (h.inputs != scenario_fingerprint(h.scenario_file))
    throw InputError(file.string() + ": the scenario " + h.scenario_file +
                     ", its model file or its records changed since the checkpoint was written; start the run again");
  Scenario sc = read_scenario(h.scenario_file);
  sc.dt_s = h.dt_s;
  sc.duration_s = h.duration_s;
  sc.ground_motion.duration_s = h.motion_duration_s;
  sc.ground_motion.start_s = h.start_s;
  sc.subdivision = h.subdivision;
  sc.cap_damping = h.cap_damping;
  options.dt_factor = 1;  // h.dt_s is the step the run used
  auto run = std::make_unique<SeismicRun>(sc, std::move(options));
  run->resume_from_ = std::move(body);
  return run;
}

SeismicRunResult SeismicRun::run() {
  const auto wall0 = Clock::now();
  const std::filesystem::path& out = options_.out;
  std::filesystem::create_directories(out);
  if (!scenario_.file.empty() && std::filesystem::exists(scenario_.file))
    std::filesystem::copy_file(scenario_.file, out / "scenario.toml", std::filesystem::copy_options::overwrite_existing);
  World& world = *world_;
  const Model& m = world.model();
  State& s = world.state();
  const double dt = dt_;

  // The masonry's joints: a soil fill's elements part and slide as soil does.
  std::vector<std::uint8_t> soil(m.block_count, 0);
  for (int b = 0; b < m.block_count; ++b) soil[b] = m.block_tag[b].part == static_cast<int>(Part::soil);
  Joints joints = find_original_joints(s, soil);
  const JointThresholds thresholds;  // 1 mm opening is a crack, 1 mm slip a slipped joint

  VtkSeriesWriter blocks(out, "blocks"), contacts(out, "contacts", VtkSeriesWriter::Kind::contacts);
  std::ostringstream history;
  history << "time_s,phase,ground_ax_m_s2,ground_ay_m_s2,ground_az_m_s2,ground_dx_m,ground_dy_m,ground_dz_m";
  for (int b : monitors_) history << ",block" << b << "_dx_m,block" << b << "_dy_m,block" << b << "_dz_m";
  history << ",kinetic_j,gravitational_j,elastic_j,damping_j,friction_j,bond_j,left_model_j,ground_work_j,balance_error_j,"
             "open_joints,cracked_joints,slipped_joints,largest_opening_m,largest_slip_m,fallen_blocks,left_model_blocks\n";

  SeismicRunResult r;
  r.joints = joints.size();
  const int crown = monitored_block();
  Vec3 settled_crown = Vec3::Zero();
  std::vector<std::uint8_t> reported_left(m.block_count, 0);
  bool shaking = false;  // settled: the ground moves
  long shake_step = 0;   // the next step of the ground motion

  auto take_counts = [&](const Counts& c) {
    r.joint_counts = c.joints;
    r.fallen_stones = c.fallen;
    r.fallen_ring_stones = c.fallen_ring;
    r.blocks_left_model = c.left_model;
    r.collapse = c.fallen_ring > 0 || c.fallen > 0.05 * m.block_count;
  };
  // Monitored displacements are relative to the ground (gd: the ground's displacement).
  auto record = [&](const char* phase, const Vec3& ga, const Vec3& gd) {
    const Counts c = count(m, s, thresholds, joints);
    for (int b = 0; b < m.block_count; ++b)
      if (s.left_model[b] && !reported_left[b]) {
        reported_left[b] = 1;
        if (options_.on_warning) {
          char text[300];
          std::snprintf(text, sizeof text, "%s fell past the edge of the ground by t = %.3f s and was frozen at (%.2f, %.2f, %.2f) m",
                        m.block_label(b).c_str(), s.time_s, s.position[b].x(), s.position[b].y(), s.position[b].z());
          options_.on_warning(text);
        }
      }
    take_counts(c);
    history.precision(9);
    history << s.time_s << "," << phase << "," << ga.x() << "," << ga.y() << "," << ga.z() << "," << gd.x() << ","
            << gd.y() << "," << gd.z();
    for (int b : monitors_) {
      const Vec3 d = s.position[b] - m.initial_position[b] - gd;
      history << "," << d.x() << "," << d.y() << "," << d.z();
    }
    const Energy& e = s.energy;
    history << "," << e.kinetic_j << "," << e.gravitational_j << "," << e.elastic_j << "," << e.damping_j << ","
            << e.friction_j << "," << e.bond_j << "," << e.left_model_j << "," << e.prescribed_work_j << ","
            << e.balance_error_j() << "," << c.joints.open << "," << c.joints.cracked << "," << c.joints.slipped << ","
            << c.joints.largest_opening_m << "," << c.joints.largest_slip_m << "," << c.fallen << "," << c.left_model << "\n";
    write_text_atomically(out / "history.csv", history.str());
    blocks.write(m, s, gd);
    contacts.write(m, s, gd, &joints);
  };
  auto write_summary = [&](bool done) {
    const Energy& e = s.energy;
    r.shaking_time_s = s.time_s - r.settle_time_s;
    r.balance_error_j = e.balance_error_j();
    r.balance_error_relative = relative_balance_error(e);
    r.steps = s.step;
    r.state_hash = world.state_hash();
    r.wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
    const JointCounts& jc = r.joint_counts;
    const int slip_joint = jc.largest_slip_joint;
    std::ostringstream j;
    j.precision(9);
    j << "{\n  \"model\": \"" << scenario_.model.name << "\",\n  \"finished\": " << (done ? "true" : "false")
      << ",\n  \"interrupted\": " << (r.interrupted ? "true" : "false") << ",\n  \"settled\": " << (r.settled ? "true" : "false")
      << ",\n  \"settle_time_s\": " << r.settle_time_s << ",\n  \"simulated_time_s\": " << s.time_s
      << ",\n  \"first_opening_time_s\": ";
    if (r.first_opening_s < 0) j << "null";
    else j << r.first_opening_s;
    j << ",\n  \"collapse\": "
      << (r.collapse ? "true" : "false") << ",\n  \"fallen_stones\": " << r.fallen_stones
      << ",\n  \"blocks_left_model\": " << r.blocks_left_model << ",\n  \"joints\": " << r.joints
      << ",\n  \"joints_open_at_end\": " << jc.open << ",\n  \"joints_cracked\": " << jc.cracked
      << ",\n  \"joints_bond_broken_while_settling\": " << r.bonds_broken_settling
      << ",\n  \"joints_slipped_at_end\": " << jc.slipped << ",\n  \"largest_opening_m\": " << jc.largest_opening_m
      << ",\n  \"largest_slip_m\": " << jc.largest_slip_m << ",\n  \"largest_slip_blocks\": ";
    if (slip_joint < 0) j << "null";
    else j << "[" << joints.block_a[slip_joint] << ", " << joints.block_b[slip_joint] << "]";
    j << ",\n  \"largest_crown_drop_m\": " << r.largest_crown_drop_m << ",\n  \"monitored_block\": " << crown
      << ",\n  \"energy_balance_error_j\": " << r.balance_error_j
      << ",\n  \"energy_balance_error_relative\": " << r.balance_error_relative << ",\n  \"dt_s\": " << dt
      << ",\n  \"damping\": \"" << (scenario_.cap_damping ? "capped" : "study") << "\""
      << ",\n  \"steps\": " << s.step << ",\n  \"threads\": " << world.thread_tuner().max_threads()
      << ",\n  \"mean_team_size\": " << (s.step > 0 ? double(s.profile.thread_steps) / s.step : 0.0) << ",\n  \"state_hash\": \"" << std::hex
      << r.state_hash << std::dec << "\"" << ",\n  \"wall_time_s\": " << r.wall_s << "\n}\n";
    write_text_atomically(out / "summary.json", j.str());
  };

  // ---- checkpoints: everything the rest of the run depends on, at an output frame ----
  const bool checkpoints = options_.checkpoint_every_s > 0 || options_.checkpoint_wall_s > 0;
  double checkpoint_time_s = s.time_s;
  auto checkpoint_wall = Clock::now();
  auto write_checkpoint = [&] {
    CheckpointHeader h{program_fingerprint(), scenario_fingerprint(scenario_.file),
                       std::filesystem::absolute(scenario_.file).string(), dt, scenario_.duration_s,
                       scenario_.ground_motion.duration_s, scenario_.ground_motion.start_s, scenario_.subdivision,
                       scenario_.cap_damping};
    write_atomically(out / "checkpoint.bin", [&](const std::filesystem::path& tmp) {
      std::ofstream file(tmp, std::ios::binary);
      CheckpointWriter w(file);
      write_header(w, h);
      w.flag(shaking), w.value(shake_step), write_result(w, r);
      for (int i = 0; i < 3; ++i) w.value(settled_crown[i]);
      w.array(reported_left), w.text(history.str()), w.array(blocks.frame_times()), w.array(contacts.frame_times());
      write_joints(w, joints);
      write_state(w, s);
      if (!file.flush()) throw std::runtime_error("cannot write " + tmp.string());
    });
    checkpoint_time_s = s.time_s;
    checkpoint_wall = Clock::now();
  };
  auto maybe_checkpoint = [&] {
    const double wall = std::chrono::duration<double>(Clock::now() - checkpoint_wall).count();
    if ((options_.checkpoint_every_s > 0 && s.time_s - checkpoint_time_s >= options_.checkpoint_every_s - 0.5 * dt) ||
        (options_.checkpoint_wall_s > 0 && wall >= options_.checkpoint_wall_s))
      write_checkpoint();
  };
  if (!resume_from_.empty()) {
    std::istringstream body(resume_from_);
    CheckpointReader in(body);
    try {
      shaking = in.flag();
      shake_step = in.value<long>();
      read_result(in, r);
      for (int i = 0; i < 3; ++i) settled_crown[i] = in.value<double>();
      in.array(reported_left);
      history.str(in.text());
      history.seekp(0, std::ios::end);
      std::vector<double> times;
      in.array(times);
      blocks.resume(times);
      in.array(times);
      contacts.resume(times);
      read_joints(in, joints);
      read_state(in, s);
    } catch (const CheckpointError& e) {
      throw InputError((out / "checkpoint.bin").string() + ": damaged checkpoint (" + e.what() + ")");
    }
    if (reported_left.size() != static_cast<std::size_t>(m.block_count) || s.position.size() != reported_left.size() ||
        s.damping_scale.size() != reported_left.size())
      throw InputError((out / "checkpoint.bin").string() + ": written for a model of another size");
    checkpoint_time_s = s.time_s;
  }

  // ---- settle under gravity until the kinetic energy is negligible ----
  const double settle_max_s = scenario_.settle_max_s;
  const long steps_per_frame = std::max(1L, std::lround(scenario_.output_interval_s / dt));
  if (!shaking) {
    if (s.step == 0) record("settle", Vec3::Zero(), Vec3::Zero());
    while (!stop_requested() && s.time_s < settle_max_s) {
      world.run(std::min<long>(steps_per_frame, std::lround((settle_max_s - s.time_s) / dt) + 1));
      record("settle", Vec3::Zero(), Vec3::Zero());
      if (s.energy.kinetic_j < scenario_.settle_kinetic_j) {
        r.settled = true;
        break;
      }
      if (checkpoints) maybe_checkpoint();
    }
    if (!stop_requested()) {
      r.settle_time_s = s.time_s;
      r.bonds_broken_settling = set_joint_reference(s, joints);  // cracks of the shaking, from the settled pose
      if (crown >= 0) settled_crown = s.position[crown];
      shaking = true;
      write_summary(false);
    }
  }

  // ---- shake: the prescribed blocks move with the ground ----
  const GroundMotion& ground = ground_;
  const long n = static_cast<long>(ground.accel_m_s2.size()) - 1;
  Vec3 ground_accel = Vec3::Zero(), ground_displacement = Vec3::Zero();  // at the last step
  if (shake_step > 0) ground_accel = ground.accel_m_s2[shake_step], ground_displacement = ground.displacement_m[shake_step];
  for (long k = shake_step; shaking && k < n && !stop_requested(); ++k) {
    const Vec3 v = 0.5 * (ground.velocity_m_s[k] + ground.velocity_m_s[k + 1]);  // exact displacement per step
    for (int b = 0; b < m.block_count; ++b)
      if (m.motion[b] == Motion::prescribed) s.velocity[b] = v;
    world.step();
    ground_accel = ground.accel_m_s2[k + 1];
    ground_displacement = ground.displacement_m[k + 1];
    if (r.first_opening_s < 0 && (k + 1) % 50 == 0 && count(m, s, thresholds, joints).joints.cracked > 0)
      r.first_opening_s = s.time_s - r.settle_time_s;
    if (crown >= 0)  // the crown's drop relative to the ground since settling
      r.largest_crown_drop_m =
          std::max(r.largest_crown_drop_m, settled_crown.z() - s.position[crown].z() + ground_displacement.z());
    shake_step = k + 1;
    if ((k + 1) % steps_per_frame == 0 || k + 1 == n) {
      record("shake", ground_accel, ground_displacement);
      write_summary(false);
      if (options_.on_frame) options_.on_frame(double(k + 1) / n);
      if (checkpoints && k + 1 < n) maybe_checkpoint();
    }
  }
  r.interrupted = stop_requested();
  if (r.interrupted) {
    if (checkpoints) write_checkpoint();  // before the extra frame: the resumed run writes its own
    record("interrupted", ground_accel, ground_displacement);
  }
  write_summary(!r.interrupted);
  return r;
}

}  // namespace ishibashi
