// Whole-run benchmark: a wall of 1,534 cubes of 0.64 m in two leaves of running bond
// (30 and 29 stones per course alternately, 26 courses) on a fixed base under gravity,
// all joints closed, dt = 4e-5 s, Nishida stone with damping ratio 0.1.
// Usage: wall_benchmark [steps [courses stones_per_course [max_threads [adaptive|fixed]]]] (any
// wall size: the scaling runs). Prints one CSV row per thread count 1, 2, 4, ... up to
// max_threads, each a fixed team: threads,blocks,pairs,subcontacts,steps,seconds,
// steps_per_s,ns_per_subcontact_step, then the per-stage times, and the peak memory. With
// a fifth argument, one row at max_threads: "fixed", or "adaptive": at most max_threads,
// the team size chosen as the run goes (engine/thread_tuner.h; threads = the mean team),
// as `ishibashi run` runs.
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "engine/world.h"
#include "geometry/demo_scenes.h"

using namespace ishibashi;

int main(int argc, char** argv) {
  const long steps = argc > 1 ? std::atol(argv[1]) : 5000;
  const int courses = argc > 2 ? std::atoi(argv[2]) : 26;
  const int stones = argc > 3 ? std::atoi(argv[3]) : 30;
  const int max_threads = argc > 4 ? std::atoi(argv[4]) : omp_get_num_procs();
  // A fifth argument: one row at max_threads, "adaptive" or not (e.g. "fixed").
  const bool one_row = argc > 5, adaptive = one_row && std::string(argv[5]) == "adaptive";
  WallSpec spec;
  spec.courses = courses;
  spec.stones_per_course = stones;
  spec.leaves = 2;
  spec.base_motion = Motion::fixed;
  // Damping ratio 0.1: with the study's critical damping (1.0) the damped stability
  // limit of a wall block is 2.1e-5 s, below the benchmark's dt of 4e-5 s.
  spec.stone = nishida_stone();
  spec.stone.damping_normal = spec.stone.damping_shear = 0.1;
  const Model model = make_wall_model(spec);

  std::printf("threads,blocks,pairs,subcontacts,steps,seconds,steps_per_s,ns_per_subcontact_step,"
              "pose_s,broadphase_s,narrowphase_and_law_s,gather_integrate_s,rebuilds,regroups\n");
  double one_thread = 0;
  for (int threads = one_row ? max_threads : 1; threads <= max_threads; threads *= 2) {
    omp_set_num_threads(threads);
    World world(model, 4e-5);
    world.set_adaptive_threads(adaptive);
    world.run(50);  // warm-up: buffers reach their size
    const State& s = world.state();
    const Profile before = s.profile;
    const auto t0 = std::chrono::steady_clock::now();
    world.run(steps);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Profile& p = s.profile;
    const double rate = steps / seconds;
    if (threads == 1) one_thread = rate;
    const auto spent = [&](Stage stage) { return p[stage].wall_s - before[stage].wall_s; };
    const double mean_team = double(p.thread_steps - before.thread_steps) / steps;
    std::printf("%.2f,%d,%zu,%zu,%ld,%.3f,%.1f,%.1f,%.3f,%.3f,%.3f,%.3f,%ld,%ld\n", mean_team, model.block_count,
                s.pairs.size(), s.contacts.size(), steps, seconds, rate, 1e9 * seconds / (steps * double(s.contacts.size())),
                spent(Stage::pose), spent(Stage::broadphase), spent(Stage::narrowphase_law),  // one pass (World::step)
                spent(Stage::gather_integrate),  // one pass with explicit dashpots (integrate.cpp)
                p.broadphase_rebuilds - before.broadphase_rebuilds, p.contact_regroups - before.contact_regroups);
    if (threads > 1 && !one_row) std::printf("# speed-up %d threads / 1 thread: %.2f\n", threads, rate / one_thread);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("# peak memory: %.1f MiB\n", usage.ru_maxrss / 1024.0);
  return 0;
}
