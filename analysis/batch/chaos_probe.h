// The chaos probe (run --probe N): how fast do two runs of one bridge part when they differ
// by far less than any physical tolerance, and how much of an ensemble's spread does chaos
// alone give? The scenario runs to a branch point just before the strong motion and writes
// a checkpoint there; N members go on from it: member 0 as it is (the reference), each
// other with every free stone moved by `perturbation_m` in a direction it draws.
//
// Outputs in the probe's folder:
//   branch/                the run to the branch point; its checkpoint.bin is the branch
//   member_000/ ...        each member's run from the branch (its series continue the
//                          branch's), with positions.bin: every block's centroid at the
//                          branch and at each output frame after it (header "ISBPOS01",
//                          the block count as uint64, then rows of float64 time_s and
//                          x, y, z of each block)
//   probe.csv              shaking time (s) and each perturbed member's separation from
//                          the reference: the largest distance between a block's centroid
//                          in the member and in the reference (m)
//   members.csv            a row per member: its perturbation, then its outcome
//   probe.json             the branch, the perturbation, each member's parting times (from
//                          the branch until the separation reached 0.1 mm, 1 mm and 1 cm)
//                          and their spread, and the outcomes as ensemble.json gives them
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/batch/mpi_ranks.h"
#include "engine/state.h"
#include "io/scenario_file.h"

namespace ishibashi {

struct ChaosProbeOptions {
  std::filesystem::path out;
  int members = 5;                 // the reference and members - 1 perturbed runs
  long seed = 1;                   // the perturbations' directions
  double perturbation_m = 1e-6;    // each free stone moved this far
  double branch_at_s = -1;         // seconds of shaking; < 0: where the strong motion begins
                                   // (5 % of the record's Arias intensity)
  int jobs = 1;                    // members at once (under mpirun: one per rank)
  int threads_per_member = 0;      // 0: the cores shared among the jobs
  double checkpoint_wall_s = 300;  // every run's checkpoint, so that an interrupted probe resumes
  std::function<void(const std::string&)> on_event;  // a line per run started or finished
  const MpiSession* mpi = nullptr;  // under mpirun, more than one rank: the runs handed out across them
};

struct ChaosProbeOutcome {
  int members = 0, finished = 0, interrupted = 0, failed = 0;
  double branch_s = 0;  // seconds of shaking at the branch
  // Per perturbed member (1 .. members - 1): seconds from the branch until its separation
  // reached 1 cm; NAN where it did not (or the member did not finish).
  std::vector<double> parted_1cm_s;
  double largest_separation_m = 0;  // of any member at any frame
};

// Under mpirun every rank calls it: one rank runs the branch on all its node's cores while
// the others wait, then rank 0 hands out the members as an ensemble's, and writes the tables
// (the outcome's counts are rank 0's; the output folder on a file system the nodes share).
ChaosProbeOutcome run_chaos_probe(const Scenario& scenario, const ChaosProbeOptions& options);

// A member's positions.bin: its rows in time order, a row rewritten after a resume counted
// once, a row cut short by a stop left out.
struct PositionSeries {
  std::size_t blocks = 0;
  std::vector<double> time_s;
  std::vector<std::vector<double>> centroid;  // (rows) (3 blocks) x, y, z of each block, m
};
PositionSeries read_positions(const std::filesystem::path& file);
// Appends the blocks' centroids now (the header first when the file is new). A header or
// row cut short (a full disk, a kill) is cut off first: it would shift every row after it.
void append_positions(const std::filesystem::path& file, const State& s);

}  // namespace ishibashi
