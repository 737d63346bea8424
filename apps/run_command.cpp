#include "apps/run_command.h"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "apps/build_command.h"
#include "engine/joints.h"
#include "engine/parallel.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "io/atomic_file.h"
#include "io/scenario_file.h"
#include "io/vtk_output.h"

namespace ishibashi {
namespace {

volatile std::sig_atomic_t interrupted = 0;
extern "C" void on_interrupt(int) { interrupted = 1; }

using Clock = std::chrono::steady_clock;

struct Counts {
  JointCounts joints;
  int fallen = 0;       // free blocks whose centroid dropped by more than their size
  int fallen_ring = 0;
  int left_model = 0;   // blocks that fell past the ground and were frozen there
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

// The balance error over the energy exchanged: the ground's work and what the dashpots,
// friction and broken bonds took.
double relative_balance_error(const Energy& e) {
  const double exchanged = std::abs(e.prescribed_work_j) + std::abs(e.damping_j) + std::abs(e.friction_j) + std::abs(e.bond_j);
  return exchanged > 0 ? e.balance_error_j() / exchanged : 0.0;
}

}  // namespace

int run_scenario(const RunOptions& o) {
  const auto wall0 = Clock::now();
  Scenario sc = read_scenario(o.scenario);
  if (o.duration_s >= 0) sc.duration_s = sc.ground_motion.duration_s = o.duration_s;
  if (o.threads >= 0) sc.threads = o.threads;
  if (o.start_s >= 0) sc.ground_motion.start_s = o.start_s;
  if (o.dt_s >= 0) sc.dt_s = o.dt_s;
  if (o.subdivision > 0) sc.subdivision = o.subdivision;
  if (sc.threads > 0) omp_set_num_threads(sc.threads);
  const std::filesystem::path out = o.out.empty() ? std::filesystem::path("out") / o.scenario.stem() : o.out;
  std::filesystem::create_directories(out);
  std::filesystem::copy_file(o.scenario, out / "scenario.toml", std::filesystem::copy_options::overwrite_existing);

  // Model: the fixed blocks move with the ground (kinematic drive).
  Model model = load_model(sc.model, sc.model_file);
  model.contact.subdivision = sc.subdivision;
  for (Motion& motion : model.motion)
    if (motion == Motion::fixed) motion = Motion::prescribed;
  int limiting_block = -1;
  const double limit_s = World(model, 1e-9).critical_time_step_s(&limiting_block);
  const double dt = (sc.dt_s > 0 ? sc.dt_s : 0.8 * limit_s) * o.dt_factor;
  const GroundMotion ground = prepare_ground_motion(sc.ground_motion, dt);
  World world(model, dt);
  const Model& m = world.model();
  State& s = world.state();
  std::vector<int> monitors = sc.monitor_blocks;
  if (monitors.empty() && crown_unit(m) >= 0) monitors.push_back(crown_unit(m));
  for (int b : monitors)
    if (b < 0 || b >= m.block_count) throw InputError(o.scenario.string() + ": [monitor] block " + std::to_string(b) + " does not exist");
  // The masonry's joints: a soil fill's elements part and slide as soil does.
  std::vector<std::uint8_t> soil(m.block_count, 0);
  for (int b = 0; b < m.block_count; ++b) soil[b] = m.block_tag[b].part == static_cast<int>(Part::soil);
  Joints joints = find_original_joints(s, soil);
  const JointThresholds thresholds;  // 1 mm opening is a crack, 1 mm slip a slipped joint

  std::printf("%s: %d blocks, %zu sub-contacts, dt = %.3g s, %d threads; ground motion %.2f s (from %.2f s of the record)\n",
              sc.model.name.c_str(), m.block_count, s.contacts.size(), dt, thread_count(), ground.duration_s(),
              sc.ground_motion.start_s);
  std::printf("  stability limit %.3g s, set by %s and its joints\n", limit_s, m.block_label(limiting_block).c_str());

  VtkSeriesWriter blocks(out, "blocks"), contacts(out, "contacts", VtkSeriesWriter::Kind::contacts);
  std::ostringstream history;
  history << "time_s,phase,ground_ax_m_s2,ground_ay_m_s2,ground_az_m_s2,ground_dx_m,ground_dy_m,ground_dz_m";
  for (int b : monitors) history << ",block" << b << "_dx_m,block" << b << "_dy_m,block" << b << "_dz_m";
  history << ",kinetic_j,gravitational_j,elastic_j,damping_j,friction_j,bond_j,left_model_j,ground_work_j,balance_error_j,"
             "open_joints,cracked_joints,slipped_joints,largest_opening_m,largest_slip_m,fallen_blocks,left_model_blocks\n";

  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  struct Summary {
    bool settled = false;
    double settle_time_s = 0, first_opening_s = -1, largest_crown_drop_m = 0;
    int bonds_broken_settling = 0;  // joints whose bond broke under self-weight
    Counts counts;
    Vec3 settled_crown = Vec3::Zero();
  } sum;
  const int crown = monitors.empty() ? -1 : monitors.front();

  std::vector<std::uint8_t> reported_left(m.block_count, 0);
  // Monitored displacements are relative to the ground (gd: the ground's displacement).
  auto record = [&](const char* phase, const Vec3& ga, const Vec3& gd) {
    const Counts c = count(m, s, thresholds, joints);
    for (int b = 0; b < m.block_count; ++b)
      if (s.left_model[b] && !reported_left[b]) {
        reported_left[b] = 1;
        std::fprintf(stderr, "\n  warning: %s fell past the edge of the ground by t = %.3f s and was frozen at (%.2f, %.2f, %.2f) m\n",
                     m.block_label(b).c_str(), s.time_s, s.position[b].x(), s.position[b].y(), s.position[b].z());
      }
    sum.counts = c;
    history.precision(9);
    history << s.time_s << "," << phase << "," << ga.x() << "," << ga.y() << "," << ga.z() << "," << gd.x() << ","
            << gd.y() << "," << gd.z();
    for (int b : monitors) {
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
    const JointCounts& jc = sum.counts.joints;
    const int slip_joint = jc.largest_slip_joint;
    std::ostringstream j;
    j.precision(9);
    j << "{\n  \"model\": \"" << sc.model.name << "\",\n  \"finished\": " << (done ? "true" : "false")
      << ",\n  \"interrupted\": " << (interrupted ? "true" : "false") << ",\n  \"settled\": " << (sum.settled ? "true" : "false")
      << ",\n  \"settle_time_s\": " << sum.settle_time_s << ",\n  \"simulated_time_s\": " << s.time_s
      << ",\n  \"first_opening_time_s\": " << (sum.first_opening_s < 0 ? "null" : std::to_string(sum.first_opening_s))
      << ",\n  \"collapse\": " << (sum.counts.fallen_ring > 0 || sum.counts.fallen > 0.05 * m.block_count ? "true" : "false")
      << ",\n  \"fallen_stones\": " << sum.counts.fallen << ",\n  \"blocks_left_model\": " << sum.counts.left_model
      << ",\n  \"joints\": " << joints.size() << ",\n  \"joints_open_at_end\": " << jc.open
      << ",\n  \"joints_cracked\": " << jc.cracked << ",\n  \"joints_bond_broken_while_settling\": " << sum.bonds_broken_settling << ",\n  \"joints_slipped_at_end\": " << jc.slipped
      << ",\n  \"largest_opening_m\": " << jc.largest_opening_m << ",\n  \"largest_slip_m\": " << jc.largest_slip_m
      << ",\n  \"largest_slip_blocks\": "
      << (slip_joint < 0 ? std::string("null")
                         : "[" + std::to_string(joints.block_a[slip_joint]) + ", " + std::to_string(joints.block_b[slip_joint]) + "]")
      << ",\n  \"largest_crown_drop_m\": " << sum.largest_crown_drop_m << ",\n  \"monitored_block\": " << crown
      << ",\n  \"energy_balance_error_j\": " << e.balance_error_j()
      << ",\n  \"energy_balance_error_relative\": " << relative_balance_error(e)
      << ",\n  \"dt_s\": " << dt << ",\n  \"steps\": " << s.step << ",\n  \"threads\": " << thread_count()
      << ",\n  \"state_hash\": \"" << std::hex << world.state_hash() << std::dec << "\""
      << ",\n  \"wall_time_s\": " << std::chrono::duration<double>(Clock::now() - wall0).count() << "\n}\n";
    write_text_atomically(out / "summary.json", j.str());
  };

  // ---- settle under gravity until the kinetic energy is negligible ----
  const long steps_per_frame = std::max(1L, std::lround(sc.output_interval_s / dt));
  record("settle", Vec3::Zero(), Vec3::Zero());
  while (!interrupted && s.time_s < sc.settle_max_s) {
    world.run(std::min<long>(steps_per_frame, std::lround((sc.settle_max_s - s.time_s) / dt) + 1));
    record("settle", Vec3::Zero(), Vec3::Zero());
    if (s.energy.kinetic_j < sc.settle_kinetic_j) {
      sum.settled = true;
      break;
    }
  }
  sum.settle_time_s = s.time_s;
  sum.bonds_broken_settling = set_joint_reference(s, joints);  // cracks of the shaking, from the settled pose
  if (crown >= 0) sum.settled_crown = s.position[crown];
  write_summary(false);

  // ---- shake: the prescribed blocks move with the ground ----
  const long n = static_cast<long>(ground.accel_m_s2.size()) - 1;
  const auto shake0 = Clock::now();
  Vec3 ground_accel = Vec3::Zero(), ground_displacement = Vec3::Zero();  // at the last step
  for (long k = 0; k < n && !interrupted; ++k) {
    const Vec3 v = 0.5 * (ground.velocity_m_s[k] + ground.velocity_m_s[k + 1]);  // exact displacement per step
    for (int b = 0; b < m.block_count; ++b)
      if (m.motion[b] == Motion::prescribed) s.velocity[b] = v;
    world.step();
    ground_accel = ground.accel_m_s2[k + 1];
    ground_displacement = ground.displacement_m[k + 1];
    if (sum.first_opening_s < 0 && (k + 1) % 50 == 0 && count(m, s, thresholds, joints).joints.cracked > 0)
      sum.first_opening_s = s.time_s - sum.settle_time_s;
    if (crown >= 0)  // the crown's drop relative to the ground since settling
      sum.largest_crown_drop_m = std::max(sum.largest_crown_drop_m, sum.settled_crown.z() - s.position[crown].z() +
                                                                        ground_displacement.z());
    if ((k + 1) % steps_per_frame == 0 || k + 1 == n) {
      record("shake", ground_accel, ground_displacement);
      write_summary(false);
      if (!o.quiet) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - shake0).count();
        const double done = double(k + 1) / n;
        std::fprintf(stderr, "\r  shaking %6.2f / %.2f s  [%-30s] %5.1f%%  %.3g s/s  ETA %4.0f s ",
                     (k + 1) * dt, n * dt, std::string(static_cast<int>(30 * done), '#').c_str(), 100 * done,
                     (k + 1) * dt / elapsed, elapsed * (1 - done) / done);
      }
    }
  }
  if (!o.quiet) std::fprintf(stderr, "\n");
  if (interrupted) record("interrupted", ground_accel, ground_displacement);
  write_summary(!interrupted);

  const Profile& p = s.profile;
  std::printf("%s after %.2f s of shaking: %d fallen stones, %d of %d joints cracked (%d open now), largest slip %.4f m, "
              "largest crown drop %.4f m, first opening %s\n",
              interrupted ? "interrupted" : "done", s.time_s - sum.settle_time_s, sum.counts.fallen, sum.counts.joints.cracked,
              joints.size(), sum.counts.joints.open, sum.counts.joints.largest_slip_m, sum.largest_crown_drop_m,
              sum.first_opening_s < 0 ? "none" : (std::to_string(sum.first_opening_s) + " s").c_str());
  std::printf("energy balance error %.3g %% of the energy exchanged\n", 100 * relative_balance_error(s.energy));
  if (o.profile) {
    const double total = p.pose_s + p.broadphase_s + p.narrowphase_s + p.contact_law_s + p.gather_s + p.integrate_s;
    std::printf("stage         seconds   share\n");
    for (const auto& [name, t] : {std::pair{"pose", p.pose_s}, {"broadphase", p.broadphase_s}, {"narrowphase", p.narrowphase_s},
                                  {"contact law", p.contact_law_s}, {"gather", p.gather_s}, {"integrate", p.integrate_s}})
      std::printf("%-12s %8.2f  %5.1f %%\n", name, t, 100 * t / total);
    std::printf("steps %ld, broadphase rebuilds %ld, contact regroups %ld, %.1f steps/s\n", s.step, p.broadphase_rebuilds,
                p.contact_regroups, s.step / total);
  }
  std::printf("outputs in %s: blocks.pvd, contacts.pvd (open in ParaView), history.csv, summary.json\n", out.c_str());
  return interrupted ? 130 : 0;
}

}  // namespace ishibashi
