// Micro-benchmarks of each pipeline stage on a settled masonry wall (two leaves of
// running bond): broadphase rebuild, narrowphase, contact law, force gather, integration.
#include <benchmark/benchmark.h>

#include "engine/pipeline.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"

using namespace ishibashi;

namespace {

World& wall() {
  static World* world = [] {
    WallSpec spec;
    spec.courses = 10;
    spec.stones_per_course = 20;
    spec.leaves = 2;
    spec.base_motion = Motion::fixed;
    auto* w = new World(make_wall_model(spec), 4e-5);
    w->run(20);
    return w;
  }();
  return *world;
}

void BM_Pose(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) update_pose(w.model(), w.state());
  st.SetItemsProcessed(st.iterations() * w.model().block_count);
}
BENCHMARK(BM_Pose);

void BM_BroadphaseRebuild(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) {
    w.state().pairs_valid = false;
    update_pairs(w.model(), w.state());
  }
  st.SetItemsProcessed(st.iterations() * w.model().block_count);
}
BENCHMARK(BM_BroadphaseRebuild);

void BM_Narrowphase(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) update_contacts(w.model(), w.state(), false);
  st.SetItemsProcessed(st.iterations() * w.state().pairs.size());
}
BENCHMARK(BM_Narrowphase);

void BM_ContactLaw(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) benchmark::DoNotOptimize(apply_contact_law(w.model(), w.state(), 0.0));
  st.SetItemsProcessed(st.iterations() * w.state().contacts.size());
}
BENCHMARK(BM_ContactLaw);

void BM_Gather(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) benchmark::DoNotOptimize(gather_forces(w.model(), w.state()));
  st.SetItemsProcessed(st.iterations() * w.state().contacts.size());
}
BENCHMARK(BM_Gather);

void BM_Integrate(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) integrate(w.model(), w.state(), 0.0);
  st.SetItemsProcessed(st.iterations() * w.model().block_count);
}
BENCHMARK(BM_Integrate);

}  // namespace

BENCHMARK_MAIN();
