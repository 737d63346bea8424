#include "apps/demo.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "analysis/run/seismic_run.h"
#include "engine/parallel.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "io/vtk_output.h"

namespace ishibashi {

int run_demo(const DemoOptions& o) {
  WallSpec spec;
  spec.courses = o.courses;
  spec.stones_per_course = o.stones_per_course;
  World world(make_wall_model(spec), o.dt_s);
  State& s = world.state();
  const Model& m = world.model();
  VtkSeriesWriter writer(o.out, "blocks");

  // Base motion. shake: 1 s of rest, then a 2 Hz sine whose amplitude grows by
  // 0.25 g per second. tilt: after 1 s, the base turns about y at 0.2 rad/s
  // (stones slide once the tilt passes the friction angle, 33 degrees, at t = 3.9 s).
  const double g = 9.81, pi = std::acos(-1.0);
  const long steps = std::lround(o.duration_s / o.dt_s);
  const long steps_per_frame = std::max(1L, std::lround(1.0 / (o.frames_per_s * o.dt_s)));
  const auto t0 = std::chrono::steady_clock::now();
  std::printf("ishibashi demo '%s': %d blocks, dt = %g s, %ld steps, %d threads\n", o.scene.c_str(), m.block_count,
              o.dt_s, steps, thread_count());
  for (long i = 0; i <= steps; ++i) {
    if (i % steps_per_frame == 0) writer.write(m, s);
    if (i == steps) break;
    const double t = s.time_s, shaking = std::max(0.0, t - 1.0);
    if (o.scene == "shake") {
      const double accel = 0.25 * g * shaking * std::sin(2 * pi * 2.0 * shaking);
      s.velocity[0].x() += accel * o.dt_s;
    } else {
      s.angular_velocity[0] = Vec3(0, t > 1.0 ? 0.2 : 0.0, 0);
      s.velocity[0] = s.angular_velocity[0].cross(s.position[0]);  // hinge: the y axis through the origin
    }
    world.step();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Energy& e = s.energy;
  std::printf("done: %.2f s simulated in %.2f s (%.0f steps/s), %d sub-contacts, %d frames\n", s.time_s, wall,
              steps / wall, sub_contact_count(s), writer.frame_count());
  std::printf("energy (J): kinetic %.4g, dissipated by dashpots %.4g, by friction %.4g, work of the base %.4g, "
              "balance error %.3g (%.3g %% of the energy exchanged)\n",
              e.kinetic_j, e.damping_j, e.friction_j, e.prescribed_work_j, e.balance_error_j(), 100.0 * relative_balance_error(e));
  std::printf("open in ParaView: %s\n", writer.pvd_path().c_str());
  return 0;
}

}  // namespace ishibashi
