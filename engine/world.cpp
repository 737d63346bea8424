#include "engine/world.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "engine/parallel.h"
#include "engine/pipeline.h"
#include "engine/team.h"

namespace ishibashi {

World::World(Model model, double dt_s)
    : model_(std::move(model)), state_(make_initial_state(model_)), dt_s_(dt_s), tuner_(thread_count()) {
  if (!(dt_s > 0) || !std::isfinite(dt_s)) throw ModelError("the time step dt must be a positive number of seconds");
  update_pose(model_, state_);
  refuse_crowded_spheres(model_, state_);
  update_pairs(model_, state_);
  update_contacts(model_, state_, /*first_detection=*/true, dt_s);

  const SubContacts& c = state_.contacts;
  for_each_sub_contact(state_, [&](int i) {
    const double overlap_limit = model_.contact_tolerance_m(c.block_a[i], c.block_b[i]);
    if (-c.gap_m[i] > overlap_limit) {
      std::ostringstream msg;
      msg << model_.block_label(c.block_a[i]) << " and " << model_.block_label(c.block_b[i]) << " overlap by "
          << -c.gap_m[i] << " m at (" << c.point[i].x() << ", " << c.point[i].y() << ", " << c.point[i].z()
          << "); initial blocks may touch but not overlap by more than " << overlap_limit << " m";
      throw ModelError(msg.str());
    }
  });
  if (model_.options.damping == Damping::capped) update_damping_caps(model_, state_, dt_s);
  int block = -1;
  const double limit = critical_time_step_s(&block);
  if (dt_s > limit) {
    std::ostringstream msg;
    msg << "time step " << dt_s << " s exceeds the stability limit " << limit << " s set by "
        << model_.block_label(block) << " and its contacts; use dt below " << limit << " s";
    throw ModelError(msg.str());
  }
}

double World::critical_time_step_s(int* block) const {
  // Capped dashpots never set the limit (they are scaled to stay within it), nor do
  // implicit ones (backward Euler damps every mode).
  const bool explicit_dashpots = model_.options.damping == Damping::study;
  return stability_limit_s(model_, state_, /*with_damping=*/explicit_dashpots, block);
}

// Runs one stage of the step, timing it into the profile: its wall time always, and
// with the team's timing on each thread's share (and the trace's slices in traced steps).
template <class Fn>
auto World::timed(Stage stage, Fn&& fn) {
  Team& team = Team::of_this_thread();
  const int threads = std::min(tuner_.threads(), Team::kMaxThreads);  // the team's largest size
  if (team.timing()) team.clear_times(threads);
  const double begin = team.now_s();
  struct Finish {
    World& world;
    Team& team;
    Stage stage;
    int threads;
    double begin;
    ~Finish() { world.note_stage(team, stage, threads, begin); }
  } finish{*this, team, stage, threads, begin};
  return fn();
}

void World::note_stage(const Team& team, Stage stage, int threads, double begin_s) {
  const double end = team.now_s();
  StageTime& t = state_.profile[stage];
  t.wall_s += end - begin_s;
  if (!team.timing()) return;
  double work = 0, slowest = 0;
  const bool traced = trace_.covers(state_.step);
  for (int i = 0; i < threads; ++i) {
    const ThreadTime& th = team.time_of(i);
    work += th.busy_s;
    slowest = std::max(slowest, th.busy_s);
    t.chunks += th.chunks;
    t.stolen += th.stolen;
    // The caller's slice is the whole stage (serial parts too), a worker's its loops' span.
    if (traced && (i == 0 || th.loops > 0))
      trace_.add({state_.step, i == 0 ? begin_s : th.begin_s, i == 0 ? end : th.end_s, th.busy_s, th.chunks, th.stolen,
                  static_cast<std::int16_t>(i), static_cast<std::int16_t>(stage)});
  }
  // The caller's time neither in chunks nor waiting for the team's: serial work.
  const ThreadTime& caller = team.time_of(0);
  const double serial = std::max(0.0, end - begin_s - caller.busy_s - caller.wait_s);
  t.team_s += (end - begin_s) * threads;
  t.serial_s += serial;
  t.work_s += work + serial;
  t.mean_s += work / threads;
  t.slowest_s += slowest;
}

void World::set_thread_timing(bool on) {
  time_threads_ = on;
  state_.profile.threads_timed = on;
}

void World::trace_steps(long first_step, long last_step) {
  set_thread_timing(true);
  trace_.first_step = first_step;
  trace_.last_step = last_step;
  // Room for every stage and the step on each thread, so the buffer never grows in a step.
  trace_.slices.clear();
  trace_.slices.reserve(std::max(0L, last_step - first_step) * (kStageCount + 1) * tuner_.max_threads());
}

namespace {
// State::driven_velocity: within a step the prescribed blocks carry the velocities that moved
// them into their pose, as the free blocks do, and the driver's for the step ahead wait
// there (integrate moves the blocks with them). A serial loop: the ground is a few blocks.
void set_aside_driven_velocities(State& s) {
  for (int b : s.prescribed_block) {
    std::swap(s.velocity[b], s.driven_velocity[b]);
    std::swap(s.angular_velocity[b], s.driven_angular_velocity[b]);
  }
}

// Once the step has moved them: the velocities that did so.
void take_driven_velocities(State& s) {
  for (int b : s.prescribed_block) {
    s.velocity[b] = s.driven_velocity[b];
    s.angular_velocity[b] = s.driven_angular_velocity[b];
  }
}
}  // namespace

void World::step() {
  const Model& m = model_;
  State& s = state_;
  Profile& p = s.profile;
  const ScopedTeamSize team(tuner_.threads());
  Team& team_of_thread = Team::of_this_thread();
  team_of_thread.set_timing(p.threads_timed || time_threads_);  // the team of the thread stepping now
  const double step_begin = team_of_thread.now_s();
  set_aside_driven_velocities(s);

  // The last step's integrate pass posed the blocks as it moved them, unless no step has
  // run since the state was made or restored.
  const bool moved = s.posed_ahead ? s.moved_ahead : timed(Stage::pose, [&] { return update_pose(m, s); });
  s.posed_ahead = false;
  const bool rebuilt = moved && timed(Stage::broadphase, [&] { return update_pairs(m, s, moved); });
  if (rebuilt) ++p.broadphase_rebuilds;
  // Caps follow the blocks' joints as they change, checked when the pair list is rebuilt
  // (a block moved half the margin): between rebuilds a block's joints barely change. They
  // come between the narrowphase and the contact law; otherwise each chunk of pairs runs
  // its law in the narrowphase's pass (one loop a step fewer).
  const bool caps = rebuilt && m.options.damping == Damping::capped;
  double elastic;  // J in the sub-contacts and ties
  if (!caps) {
    ContactLaw law(m, s, dt_s_, /*clocked=*/team_of_thread.timing());
    elastic = timed(Stage::narrowphase_law, [&] {
      update_contacts(m, s, /*first_detection=*/false, dt_s_, &law);
      return law.finish();
    });
    if (team_of_thread.timing()) p[Stage::narrowphase_law].law_work_s += law.seconds();
  } else {
    timed(Stage::narrowphase, [&] { update_contacts(m, s, /*first_detection=*/false, dt_s_); });
    timed(Stage::damping_caps, [&] { update_damping_caps(m, s, dt_s_); });
    elastic = timed(Stage::contact_law, [&] { return apply_contact_law(m, s, dt_s_); });
  }
  double prescribed_power = 0;
  BlockEnergy before;
  if (m.options.damping == Damping::implicit) {
    const DampingSolve solve = timed(Stage::gather_damping_solve, [&] { return solve_implicit_damping(m, s, dt_s_); });
    p.damping_iterations += solve.iterations;
    if (!solve.converged) ++p.damping_unconverged;
    const ForcesAndMotion pass = timed(Stage::integrate, [&] { return integrate_with_dashpots(m, s, dt_s_); });
    prescribed_power = solve.contact_power_w;
    s.energy.damping_j -= pass.dashpot_work_j + solve.prescribed_work_j;
    s.energy.prescribed_work_j += solve.prescribed_power_w * dt_s_;
    before = pass.energy;
  } else {
    const ForcesAndMotion pass = timed(Stage::gather_integrate, [&] { return gather_and_integrate(m, s, dt_s_); });
    prescribed_power = pass.prescribed_power_w;
    before = pass.energy;
  }
  take_driven_velocities(s);

  // Energy at this step, i.e. of the pose and the velocities integrate started from. v
  // was last updated between the previous pose and this one, so the potential is
  // averaged over the two poses: that is the quantity semi-implicit Euler conserves to
  // second order.
  Energy& e = s.energy;
  const double gravitational = before.gravitational_j;
  if (!s.energy_started) {
    s.last_gravitational_j = gravitational;
    s.last_elastic_j = elastic;
    e.initial_total_j = before.kinetic_j + gravitational + elastic;
    s.energy_started = true;
  }
  e.kinetic_j = before.kinetic_j;
  e.gravitational_j = 0.5 * (s.last_gravitational_j + gravitational);
  e.elastic_j = 0.5 * (s.last_elastic_j + elastic);
  s.last_gravitational_j = gravitational;
  s.last_elastic_j = elastic;
  e.prescribed_work_j += prescribed_power * dt_s_;
  e.left_model_j += before.left_model_j;

  const double step_end = team_of_thread.now_s();
  if (trace_.covers(s.step)) trace_.add({s.step, step_begin, step_end, 0, 0, 0, 0, -1});
  s.time_s += dt_s_;
  ++s.step;
  p.thread_steps += tuner_.threads();
  tuner_.record(step_end - step_begin);
}

int World::form_bonds() { return ishibashi::form_bonds(model_, state_); }

namespace {
// FNV-1a over raw bytes.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void mix(const void* data, std::size_t bytes) {
    const unsigned char* c = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ c[i]) * 1099511628211ull;
  }
};

void mix_blocks(const Model& m, const State& s, Fnv& f) {
  for (int b = 0; b < m.block_count; ++b) {
    f.mix(s.position[b].data(), sizeof(double) * 3);
    f.mix(s.orientation[b].coeffs().data(), sizeof(double) * 4);
    f.mix(s.velocity[b].data(), sizeof(double) * 3);
    f.mix(s.angular_velocity[b].data(), sizeof(double) * 3);
  }
}
}  // namespace

std::uint64_t World::state_hash() const {
  Fnv f;
  mix_blocks(model_, state_, f);
  for (const Pair& pair : state_.pairs)  // in pair order: the same bytes, dense or not
    if (pair.sub_count > 0) f.mix(state_.contacts.shear_stretch_m.data() + pair.sub_begin, sizeof(Vec3) * pair.sub_count);
  return f.h;
}

std::uint64_t World::motion_hash() const {
  Fnv f;
  mix_blocks(model_, state_, f);
  return f.h;
}

}  // namespace ishibashi
