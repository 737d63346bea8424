// Micro-benchmarks of each pipeline stage on a settled masonry wall (two leaves of
// running bond): pose, broadphase rebuild, narrowphase (carried over and re-clipped),
// contact law, force gather, integration; and the narrowphase of one pair in each
// contact configuration (face-face, edge-face, vertex-face, edge-edge), re-searched and
// re-clipped on every iteration (each includes one OpenMP region, about 1 us).
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>

#include "engine/pipeline.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "geometry/materials.h"
#include "geometry/shapes.h"

using namespace ishibashi;

namespace {

// Two leaves of running bond, 10 courses of 20 Nishida stones on a fixed base.
WallSpec benchmark_wall() {
  WallSpec spec;
  spec.courses = 10;
  spec.stones_per_course = 20;
  spec.leaves = 2;
  spec.base_motion = Motion::fixed;
  spec.stone = nishida_stone();
  return spec;
}

World& wall() {
  static World* world = [] {
    WallSpec spec = benchmark_wall();
    spec.stone.damping_normal = spec.stone.damping_shear = 0.1;  // stable at 4e-5 s, as in wall_benchmark
    auto* w = new World(make_wall_model(spec), 4e-5);
    w->run(20);
    return w;
  }();
  return *world;
}

// The same wall with the study's h = 1 dashpots integrated implicitly (Damping::implicit)
// at 4e-5 s, after 20 steps of settling.
World& implicit_wall() {
  static World* world = [] {
    Model model = make_wall_model(benchmark_wall());
    model.options.damping = Damping::implicit;
    auto* w = new World(std::move(model), 4e-5);
    w->run(20);
    return w;
  }();
  return *world;
}

// Makes every pair that touches redo its axis search and clipping on the next narrowphase,
// as after a large relative motion: its remembered offset is put a million kilometres away
// (a turn could be a stone's real one: the wall has stones turned half a turn) and its
// bound on the motion since made unknown.
constexpr double kFarOffsetM = 1e9;
void forget_search(State& s) {
  for (Pair& p : s.pairs) {
    p.offset_at_search = Vec3::Constant(kFarOffsetM);
    p.moved_bound_m = std::numeric_limits<double>::infinity();  // else the bound skips the test
  }
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

// A rebuild's cost per block as the wall grows on its base slab (stones per course =
// 2 x courses, two leaves): flat when the slab, larger than every stone, stays out of
// the grid; growing with the block count when the slab sizes the cells.
void BM_BroadphaseRebuildScaling(benchmark::State& st) {
  WallSpec spec;
  spec.courses = static_cast<int>(st.range(0));
  spec.stones_per_course = 2 * spec.courses;
  spec.leaves = 2;
  spec.base_motion = Motion::fixed;
  spec.stone = nishida_stone();
  const Model model = make_wall_model(spec);
  State state = make_initial_state(model);
  for (auto _ : st) {
    state.pairs_valid = false;
    update_pairs(model, state);
  }
  st.SetItemsProcessed(st.iterations() * model.block_count);
}
BENCHMARK(BM_BroadphaseRebuildScaling)->Arg(10)->Arg(20)->Arg(40);

// The common case in a standing structure: every joint barely moved, updated in place.
void BM_NarrowphaseCarriedOver(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) update_contacts(w.model(), w.state(), false, w.dt_s());
  st.SetItemsProcessed(st.iterations() * w.state().contacts.size());
  st.counters["pairs"] = static_cast<double>(w.state().pairs.size());
}
BENCHMARK(BM_NarrowphaseCarriedOver);

// Every pair re-searched and re-clipped, as in a collapse.
void BM_NarrowphaseReclipped(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) {
    st.PauseTiming();
    forget_search(w.state());
    st.ResumeTiming();
    update_contacts(w.model(), w.state(), false, w.dt_s());
  }
  for (const Pair& p : w.state().pairs)
    if (p.sub_count > 0 && p.offset_at_search == Vec3::Constant(kFarOffsetM)) {
      st.SkipWithError("a touching pair was not searched anew");
      break;
    }
  st.SetItemsProcessed(st.iterations() * w.state().contacts.size());
}
BENCHMARK(BM_NarrowphaseReclipped);

// One fixed unit cube (top at z = 0) and `top` above it.
struct PairScene {
  Model model;
  State state;
};
PairScene pair_scene(const Polyhedron& top, const Polyhedron& bottom = make_box(Vec3(0, 0, -0.5), Vec3(1, 1, 1))) {
  ModelBuilder b;
  const int mat = b.add_material(nishida_stone());
  b.add_block(bottom.vertices, bottom.faces, mat, Motion::fixed);
  b.add_block(top.vertices, top.faces, mat);
  PairScene scene{b.build(), {}};
  scene.state = make_initial_state(scene.model);
  update_pose(scene.model, scene.state);
  update_pairs(scene.model, scene.state);
  update_contacts(scene.model, scene.state, true, 1e-5);
  return scene;
}

void run_pair(benchmark::State& st, PairScene scene) {
  for (auto _ : st) {
    forget_search(scene.state);
    update_contacts(scene.model, scene.state, false, 1e-5);
  }
  st.counters["subcontacts"] = static_cast<double>(scene.state.contacts.size());
}

void BM_PairFaceFace(benchmark::State& st) {  // a cube turned 45 degrees, one corner past the edge: 5 points
  const Polyhedron top = transformed(make_box(Vec3::Zero(), Vec3(0.6, 0.6, 0.6)),
                                     Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix(), Vec3(0.1, 0, 0.3));
  run_pair(st, pair_scene(top));
}
BENCHMARK(BM_PairFaceFace);

void BM_PairEdgeFace(benchmark::State& st) {
  const Polyhedron top = transformed(make_box(Vec3::Zero(), Vec3(0.6, 0.4, 0.4)),
                                     Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix(),
                                     Vec3(0, 0, 0.2 * std::sqrt(2.0)));
  run_pair(st, pair_scene(top));
}
BENCHMARK(BM_PairEdgeFace);

void BM_PairVertexFace(benchmark::State& st) {
  const Mat3 r = Quat::FromTwoVectors(Vec3(-1, -1, -1).normalized(), -Vec3::UnitZ()).toRotationMatrix();
  run_pair(st, pair_scene(transformed(make_box(Vec3::Zero(), Vec3(0.4, 0.4, 0.4)), r, Vec3(0, 0, 0.2 * std::sqrt(3.0)))));
}
BENCHMARK(BM_PairVertexFace);

void BM_PairEdgeEdge(benchmark::State& st) {  // two bars on edge, crossing at right angles
  const double h = 0.1 * std::sqrt(2.0);
  const Polyhedron lower = transformed(make_box(Vec3::Zero(), Vec3(2, 0.2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix(), Vec3(0, 0, -h));
  const Polyhedron upper = transformed(make_box(Vec3::Zero(), Vec3(0.2, 2, 0.2)),
                                       Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()).toRotationMatrix(), Vec3(0, 0, h - 1e-5));
  run_pair(st, pair_scene(upper, lower));
}
BENCHMARK(BM_PairEdgeEdge);

void BM_ContactLaw(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) benchmark::DoNotOptimize(apply_contact_law(w.model(), w.state(), 0.0));
  st.SetItemsProcessed(st.iterations() * w.state().contacts.size());
}
BENCHMARK(BM_ContactLaw);

// One solve of the implicit dashpots (its first pass gathers the forces) from the same
// state and first guess each time, at a step that refreshes the preconditioner (Arg 1,
// one in kPreconditionerRefreshSteps) or not.
void BM_ImplicitDampingSolve(benchmark::State& st) {
  World& w = implicit_wall();
  State& s = w.state();
  s.step = kPreconditionerRefreshSteps * 1000 + (st.range(0) ? 0 : 1);
  const std::vector<Vec6> first_guess = s.implicit.delta;
  double iterations = 0;
  for (auto _ : st) {
    s.implicit.delta = first_guess;
    iterations += solve_implicit_damping(w.model(), s, 4e-5).iterations;
  }
  st.counters["iterations"] = iterations / static_cast<double>(st.iterations());
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(s.pairs.size()));
}
BENCHMARK(BM_ImplicitDampingSolve)->Arg(0)->Arg(1);

// Explicit dashpots: the gather and integrate as one pass (World::step).
void BM_GatherAndIntegrate(benchmark::State& st) {
  World& w = wall();
  for (auto _ : st) benchmark::DoNotOptimize(gather_and_integrate(w.model(), w.state(), 0.0));
  st.SetItemsProcessed(st.iterations() * w.model().block_count);
}
BENCHMARK(BM_GatherAndIntegrate);

}  // namespace

BENCHMARK_MAIN();
