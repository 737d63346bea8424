// Ensembles of seismic runs (a scenario's [ensemble] table, run --members): members that
// differ by what a real bridge is uncertain about (analysis/run/member_draw.h). Near its
// capacity a bridge's fate in one run is decided by details nobody knows; the ensemble
// gives its outcomes as probabilities with their sampling error (Wilson intervals).
//
// Outputs in the ensemble's folder:
//   member_000/ ...        each member's run: series, history.csv, summary.json (its draws
//                          under "member"), checkpoint.bin while it runs
//   ensemble.csv           a row per member: member, seed, amplitude, friction_angle_deg,
//                          then summary.json's result columns (run_result.h), first_fall_s
//                          and stopped_early (yes: ended at its collapse, [run] stop_at)
//   ensemble.json          the probabilities of collapse, of any stone falling and of a
//                          ring stone falling, each with its 95 % Wilson interval, and the
//                          median, least and largest fallen stones, first opening, first
//                          fall and crown drop, and in how many members each stone fell
//   fallen_share.vtu       the model's blocks, cell array fallen_share: the share of the
//                          members in which each fell (ParaView)
#pragma once
#include <array>
#include <filesystem>
#include <functional>
#include <string>

#include "analysis/batch/member_runs.h"
#include "analysis/batch/mpi_ranks.h"
#include "io/scenario_file.h"

namespace ishibashi {

struct EnsembleOptions {
  std::filesystem::path out;
  int members = 0;                 // > 0: replaces the scenario's
  long seed = -1;                  // >= 0: replaces the scenario's
  int jobs = 1;                    // members at once (under mpirun: one per rank)
  int first_member = 0;            // run members [first_member, end_member) only (a machine's share of
  int end_member = -1;             //   an ensemble); -1: to the last member
  int threads_per_member = 0;      // 0: the cores shared among the jobs
  double checkpoint_wall_s = 300;  // each member's checkpoint, so that an interrupted ensemble resumes
  std::function<void(const std::string&)> on_event;  // a line per member started or finished
  // Each member that finished running (not one kept from before) draws its report.png
  // where it ran (analysis/report/run_report.py), titled report_title and its number; a
  // picture it cannot draw is an event saying why.
  bool member_reports = false;
  std::string report_title;
  const MpiSession* mpi = nullptr;  // under mpirun, more than one rank: members handed out across them
};

struct EnsembleOutcome {
  int members = 0, ran = 0, current = 0, failed = 0, interrupted = 0;  // current: finished before, kept
  int collapses = 0, stones_fell = 0, ring_stones_fell = 0;            // among the finished members
  int finished = 0;
  int typical_member = -1, worst_member = -1;  // of the most common and the worst outcome (member_runs.h)
  std::vector<std::pair<std::string, int>> failure_modes;  // members by how they fail, the most common first
};

// Runs the members of [first_member, end_member) not yet finished (a member's folder
// stamped with the same inputs is kept; one with a checkpoint resumes from it), then
// writes ensemble.csv and ensemble.json from every finished member's summary.json in the
// folder, whichever run or machine ran it: members run in shares on several machines by
// the same build are merged by copying their member_NNN folders into one folder. Under
// mpirun every rank calls it; rank 0 hands out the members (one per rank at a time, each on
// its node's cores shared among the node's ranks) and writes the tables, and only its
// outcome counts every member (the others': their own runs).
EnsembleOutcome run_ensemble(const Scenario& scenario, const EnsembleOptions& options);

}  // namespace ishibashi
