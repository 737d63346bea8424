// Where a step's time goes: per stage, the wall time and how the team's threads spent it
// (run --profile), and optionally a timeline of chosen steps (run --trace).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace ishibashi {

// The stages of World::step in the order it calls them.
// narrowphase_law: each chunk of pairs runs its contact law in the narrowphase's pass;
// only where the damping caps must come between them (capped dashpots, on a step that
// rebuilt the pair list) are they the stages narrowphase and contact_law.
// gather_integrate: both in one pass (explicit dashpots); with implicit ones the gather is
// the solve's first pass (gather_damping_solve) and integrate adds the solve's impulse.
// Either integrate poses the blocks for the next step (pose.cpp), so the pose stage runs
// only on a run's first step and after a restore.
enum class Stage : std::uint8_t {
  pose,
  broadphase,
  narrowphase_law,
  narrowphase,
  damping_caps,
  contact_law,
  gather_damping_solve,
  integrate,
  gather_integrate
};
constexpr int kStageCount = 9;
constexpr std::array<const char*, kStageCount> kStageNames = {
    "pose", "broadphase", "narrowphase+contact law", "narrowphase", "damping caps", "contact law",
    "gather+damping solve", "integrate+pose", "gather+integrate+pose"};

// One stage's time, summed over the steps. The thread times (Team::set_timing) are
// measured only while a run profiles or traces; wall_s always.
struct StageTime {
  double wall_s = 0;     // on the calling thread, serial parts included
  double team_s = 0;     // wall_s times the team size: the thread-seconds the stage held
  double work_s = 0;     // thread-seconds claiming and running chunks, and the caller's serial parts
  double serial_s = 0;   // the caller's serial parts (the rest of the team waits through them)
  double mean_s = 0;     // sum over calls of work / team size
  double slowest_s = 0;  // sum over calls of the busiest thread's work
  double chunks = 0;     // chunks run, summed over calls
  double stolen = 0;     // of them, chunks a thread took from another's range (its data in another core's cache)
  // narrowphase_law: the thread-seconds of work in the contact law's part (its chunks'
  // own clock, and the serial end: energies summed, ties); the rest of work_s is the
  // narrowphase's.
  double law_work_s = 0;
  // Threads' time waiting (at the loops' ends, or while the caller runs serial parts).
  double wait_s() const { return team_s - work_s; }
  // The busiest thread against the mean: 1 when the chunks spread evenly.
  double imbalance() const { return mean_s > 0 ? slowest_s / mean_s : 1.0; }
  // The share of chunks run off their thread's own range: 0 when every range kept pace.
  double stolen_share() const { return chunks > 0 ? stolen / chunks : 0.0; }
  StageTime& operator-=(const StageTime& e) {
    wall_s -= e.wall_s, team_s -= e.team_s, work_s -= e.work_s, serial_s -= e.serial_s;
    mean_s -= e.mean_s, slowest_s -= e.slowest_s, chunks -= e.chunks, stolen -= e.stolen, law_work_s -= e.law_work_s;
    return *this;
  }
};

// One thread's part of one stage of one step, seconds on the team's clock (Team::now_s).
struct TraceSlice {
  long step = 0;
  double begin_s = 0, end_s = 0, busy_s = 0;
  int chunks = 0, stolen = 0;  // as ThreadTime's
  std::int16_t thread = 0;
  std::int16_t stage = -1;  // -1: the whole step (caller's track)
};

// The slices of steps [first_step, last_step), kept in a buffer sized before the run.
struct StageTrace {
  long first_step = 0, last_step = 0;
  std::vector<TraceSlice> slices;
  bool covers(long step) const { return step >= first_step && step < last_step; }
  // A slice if the buffer has room (it never grows inside a step); false when full.
  bool add(const TraceSlice& slice) {
    if (slices.size() == slices.capacity()) return false;
    slices.push_back(slice);
    return true;
  }
};

struct Profile {
  std::array<StageTime, kStageCount> stages{};
  bool threads_timed = false;   // team_s, work_s, mean_s and slowest_s measured
  long damping_iterations = 0;   // conjugate-gradient iterations, summed over the steps
  long damping_unconverged = 0;  // steps whose solve stopped at kDampingSolveMaxIterations
  long broadphase_rebuilds = 0;
  long contact_regroups = 0;  // steps whose sub-contact arrays were regrouped (a count changed)
  long thread_steps = 0;      // sum over steps of the team size (/ steps: the mean team)

  // The steps since `earlier`, a copy of this profile taken before them (a resumed run's
  // own steps: the checkpoint's profile is the run's from its start).
  Profile since(const Profile& earlier) const {
    Profile d = *this;
    for (int k = 0; k < kStageCount; ++k) d.stages[k] -= earlier.stages[k];
    d.damping_iterations -= earlier.damping_iterations;
    d.damping_unconverged -= earlier.damping_unconverged;
    d.broadphase_rebuilds -= earlier.broadphase_rebuilds;
    d.contact_regroups -= earlier.contact_regroups;
    d.thread_steps -= earlier.thread_steps;
    return d;
  }
  StageTime& operator[](Stage s) { return stages[static_cast<int>(s)]; }
  const StageTime& operator[](Stage s) const { return stages[static_cast<int>(s)]; }
  double wall_s() const {
    double total = 0;
    for (const StageTime& s : stages) total += s.wall_s;
    return total;
  }
};

}  // namespace ishibashi
