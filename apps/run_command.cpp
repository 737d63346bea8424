#include "apps/run_command.h"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "apps/build_command.h"
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
  int broken = 0;   // sub-contacts that lost their bond
  int cracked = 0;  // original sub-contacts broken or open by more than `opening_m`
  int fallen = 0;   // free blocks whose centroid dropped by more than their size
  int fallen_ring = 0;
};

Counts count(const Model& m, const State& s, double opening_m, int original_total) {
  Counts c;
  int original_now = 0;
  for (std::size_t i = 0; i < s.contacts.size(); ++i) {
    const std::uint8_t f = s.contacts.flags[i];
    c.broken += (f & SubContactFlag::broken) != 0;
    if (!(f & SubContactFlag::original)) continue;
    ++original_now;
    c.cracked += (f & SubContactFlag::broken) || s.contacts.gap_m[i] > opening_m;
  }
  c.cracked += std::max(0, original_total - original_now);  // opened beyond the contact tolerance
  for (int b = 0; b < m.block_count; ++b)
    if (is_fallen(m, s, b)) {
      ++c.fallen;
      c.fallen_ring += m.block_tag[b].part == static_cast<int>(Part::ring);
    }
  return c;
}

}  // namespace

int run_scenario(const RunOptions& o) {
  const auto wall0 = Clock::now();
  Scenario sc = read_scenario(o.scenario);
  if (o.duration_s >= 0) sc.duration_s = sc.ground_motion.duration_s = o.duration_s;
  if (o.threads >= 0) sc.threads = o.threads;
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
  const double dt = sc.dt_s > 0 ? sc.dt_s : 0.8 * limit_s;
  const GroundMotion ground = prepare_ground_motion(sc.ground_motion, dt);
  World world(model, dt);
  const Model& m = world.model();
  State& s = world.state();
  std::vector<int> monitors = sc.monitor_blocks;
  if (monitors.empty() && crown_unit(m) >= 0) monitors.push_back(crown_unit(m));
  for (int b : monitors)
    if (b < 0 || b >= m.block_count) throw InputError(o.scenario.string() + ": [monitor] block " + std::to_string(b) + " does not exist");
  int original_total = 0;
  for (std::uint8_t f : s.contacts.flags) original_total += (f & SubContactFlag::original) != 0;
  const double opening = 1e-3;  // m: an original joint open by more than this has cracked

  std::printf("%s: %d blocks, %zu sub-contacts, dt = %.3g s, %d threads; ground motion %.2f s (from %.2f s of the record)\n",
              sc.model.name.c_str(), m.block_count, s.contacts.size(), dt, thread_count(), ground.duration_s(),
              sc.ground_motion.start_s);
  std::printf("  stability limit %.3g s, set by %s and its joints\n", limit_s, m.block_label(limiting_block).c_str());

  VtkSeriesWriter blocks(out, "blocks"), contacts(out, "contacts", VtkSeriesWriter::Kind::contacts);
  std::ostringstream history;
  history << "time_s,phase,ground_ax_m_s2,ground_ay_m_s2,ground_az_m_s2,ground_dx_m,ground_dy_m,ground_dz_m";
  for (int b : monitors) history << ",block" << b << "_dx_m,block" << b << "_dy_m,block" << b << "_dz_m";
  history << ",kinetic_j,gravitational_j,elastic_j,damping_j,friction_j,bond_j,ground_work_j,balance_error_j,"
             "broken_subcontacts,cracked_subcontacts,fallen_blocks\n";

  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  struct Summary {
    bool settled = false;
    double settle_time_s = 0, first_crack_s = -1, largest_crown_drop_m = 0;
    Counts counts;
    Vec3 settled_crown = Vec3::Zero();
  } sum;
  const int crown = monitors.empty() ? -1 : monitors.front();

  // Monitored displacements are relative to the ground (gd: the ground's displacement).
  auto record = [&](const char* phase, const Vec3& ga, const Vec3& gd) {
    const Counts c = count(m, s, opening, original_total);
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
            << e.friction_j << "," << e.bond_j << "," << e.prescribed_work_j << "," << e.balance_error_j() << ","
            << c.broken << "," << c.cracked << "," << c.fallen << "\n";
    write_text_atomically(out / "history.csv", history.str());
    blocks.write(m, s);
    contacts.write(m, s);
  };
  auto write_summary = [&](bool done) {
    const Energy& e = s.energy;
    const double work = std::abs(e.prescribed_work_j) + std::abs(e.damping_j) + std::abs(e.friction_j);
    std::ostringstream j;
    j.precision(9);
    j << "{\n  \"model\": \"" << sc.model.name << "\",\n  \"finished\": " << (done ? "true" : "false")
      << ",\n  \"interrupted\": " << (interrupted ? "true" : "false") << ",\n  \"settled\": " << (sum.settled ? "true" : "false")
      << ",\n  \"settle_time_s\": " << sum.settle_time_s << ",\n  \"simulated_time_s\": " << s.time_s
      << ",\n  \"first_crack_time_s\": " << (sum.first_crack_s < 0 ? "null" : std::to_string(sum.first_crack_s))
      << ",\n  \"collapse\": " << (sum.counts.fallen_ring > 0 || sum.counts.fallen > 0.05 * m.block_count ? "true" : "false")
      << ",\n  \"fallen_stones\": " << sum.counts.fallen << ",\n  \"broken_subcontacts\": " << sum.counts.broken
      << ",\n  \"largest_crown_drop_m\": " << sum.largest_crown_drop_m << ",\n  \"monitored_block\": " << crown
      << ",\n  \"energy_balance_error_j\": " << e.balance_error_j()
      << ",\n  \"energy_balance_error_relative\": " << (work > 0 ? e.balance_error_j() / work : 0.0)
      << ",\n  \"dt_s\": " << dt << ",\n  \"steps\": " << s.step << ",\n  \"threads\": " << thread_count()
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
  if (crown >= 0) sum.settled_crown = s.position[crown];
  write_summary(false);

  // ---- shake: the prescribed blocks move with the ground ----
  const long n = static_cast<long>(ground.accel_m_s2.size()) - 1;
  const auto shake0 = Clock::now();
  for (long k = 0; k < n && !interrupted; ++k) {
    const Vec3 v = 0.5 * (ground.velocity_m_s[k] + ground.velocity_m_s[k + 1]);  // exact displacement per step
    for (int b = 0; b < m.block_count; ++b)
      if (m.motion[b] == Motion::prescribed) s.velocity[b] = v;
    world.step();
    if (sum.first_crack_s < 0 && (k + 1) % 50 == 0 && count(m, s, opening, original_total).cracked > 0)
      sum.first_crack_s = s.time_s - sum.settle_time_s;
    if (crown >= 0)  // the crown's drop relative to the ground since settling
      sum.largest_crown_drop_m = std::max(sum.largest_crown_drop_m, sum.settled_crown.z() - s.position[crown].z() +
                                                                        ground.displacement_m[k + 1].z());
    if ((k + 1) % steps_per_frame == 0 || k + 1 == n) {
      record("shake", ground.accel_m_s2[k + 1], ground.displacement_m[k + 1]);
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
  if (interrupted) record("interrupted", Vec3::Zero(), Vec3::Zero());
  write_summary(!interrupted);

  const Profile& p = s.profile;
  std::printf("%s after %.2f s of shaking: %d fallen stones, %d broken sub-contacts, largest crown drop %.4f m, first crack %s\n",
              interrupted ? "interrupted" : "done", s.time_s - sum.settle_time_s, sum.counts.fallen, sum.counts.broken,
              sum.largest_crown_drop_m, sum.first_crack_s < 0 ? "none" : (std::to_string(sum.first_crack_s) + " s").c_str());
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
