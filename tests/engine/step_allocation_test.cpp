// The time step allocates nothing once its buffers have grown (STYLE: no heap allocation
// inside the step): a shaken wall, whose sub-contact arrays are regrouped and whose pair
// list is rebuilt, steps thousands of times without one operator new. Buffers only grow,
// so a step may allocate when one first reaches a new size (the warm-up below), never
// again at a size it has held. Its own program: it replaces the global operator new.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "engine/world.h"
#include "geometry/demo_scenes.h"

namespace {
std::atomic<long> allocations{0};
std::atomic<bool> counting{false};

void* allocate(std::size_t bytes, std::size_t alignment) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + alignment - 1) / alignment * alignment;
  void* p = alignment <= alignof(std::max_align_t) ? std::malloc(rounded) : std::aligned_alloc(alignment, rounded);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t bytes) { return allocate(bytes, alignof(std::max_align_t)); }
void* operator new[](std::size_t bytes) { return allocate(bytes, alignof(std::max_align_t)); }
void* operator new(std::size_t bytes, std::align_val_t a) { return allocate(bytes, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t bytes, std::align_val_t a) { return allocate(bytes, static_cast<std::size_t>(a)); }
// Not inlined: GCC would then see free() of what operator new returned and warn of a
// mismatch (-Wmismatched-new-delete) that is none, since operator new above calls malloc.
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace ishibashi {
namespace {

struct Window {
  long allocations = 0, rebuilds = 0, regroups = 0;
};

// The determinism test's wall (141 blocks, two leaves) on a base shaken at 0.8 g, 5 Hz:
// the counts of steps [warm_up, steps), on one thread (a team's threads each grow their
// own scratch to the largest manifold they have met, so which thread meets it first, and
// allocates, varies from run to run).
Window shaken_wall_window(Damping damping, int warm_up, int steps) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  WallSpec spec;
  spec.courses = 5;
  spec.stones_per_course = 14;
  spec.leaves = 2;
  spec.options.damping = damping;
  World w(make_wall_model(spec), damping == Damping::study ? 1e-5 : 3e-5);
  State& s = w.state();
  const auto counts_now = [&] {
    return Window{allocations.load(), s.profile.broadphase_rebuilds, s.profile.contact_regroups};
  };
  Window at_warm_up;
  for (int i = 0; i < steps; ++i) {
    if (i == warm_up) at_warm_up = counts_now();
    s.velocity[0].x() += 0.8 * 9.81 * std::sin(2 * M_PI * 5.0 * s.time_s) * w.dt_s();
    counting = true;
    w.step();
    counting = false;
  }
  const Window end = counts_now();
  omp_set_num_threads(saved);
  return {end.allocations - at_warm_up.allocations, end.rebuilds - at_warm_up.rebuilds,
          end.regroups - at_warm_up.regroups};
}

TEST(StepAllocation, NoneOnceTheBuffersHaveGrown) {
  // Explicit dashpots at 1e-5 s: 0.06 s of shaking, the sub-contact arrays regrouped
  // hundreds of times as joints open and close.
  const Window study = shaken_wall_window(Damping::study, 4000, 10000);
  EXPECT_GT(study.regroups, 100);
  EXPECT_EQ(study.allocations, 0);
  // Implicit dashpots at 3e-5 s (the solve's arrays too): the stones move farther, and the
  // pair list is rebuilt as well.
  const Window implicit = shaken_wall_window(Damping::implicit, 4000, 10000);
  EXPECT_GT(implicit.regroups, 100);
  EXPECT_GT(implicit.rebuilds, 0);
  EXPECT_EQ(implicit.allocations, 0);
}

}  // namespace
}  // namespace ishibashi
