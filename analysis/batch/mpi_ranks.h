// Many runs across machines with MPI (sweeps, ensembles, the study): rank 0 hands out jobs
// one at a time as ranks ask for them (dynamic assignment: a rank that finishes takes the
// next), and each rank's answer for its last job comes back with its next request. The
// output folder must be on a file system every node shares; each job writes only its own
// folder.
#pragma once
#include <functional>
#include <string>

#include "analysis/batch/job_queue.h"

namespace ishibashi {

// MPI for the lifetime of a set of runs when the program was started by mpirun (or another
// launcher that sets PMI_RANK / OMPI_COMM_WORLD_SIZE); otherwise a single process.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  int ranks_on_this_node() const { return local_size_; }

 private:
  bool active_ = false;
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

// Rank 0, on its main thread, beside its own workers: hands the jobs of `queue` to the other
// ranks as they ask, until each of them has been told that none is left. Each answer (a job's
// result, never empty) goes to on_answer(answer, rank), each job handed out to on_handed(job,
// rank). It polls, so that it takes no core from this rank's own runs.
void serve_other_ranks(JobQueue& queue, const MpiSession& mpi,
                       const std::function<void(const std::string& answer, int rank)>& on_answer,
                       const std::function<void(int job, int rank)>& on_handed);

// Any other rank: asks rank 0 for a job, runs it and sends what it returns (not empty) with
// the next request, until rank 0 has none left.
void work_for_rank_zero(const std::function<std::string(int job)>& job);

}  // namespace ishibashi
