// Many runs across machines with MPI (sweeps, ensembles, the study): rank 0 hands out jobs
// one at a time as ranks ask for them (dynamic assignment: a rank that finishes takes the
// next), and each rank's answer for its last job comes back with its next request. The
// output folder must be on a file system every node shares; each job writes only its own
// folder.
#pragma once
#include <functional>
#include <string>
#include <vector>

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

// Runs job(i) for every job i of `jobs` (in their order): on `workers` threads of this
// process (this one among them), or, under mpirun with more than one rank, one job per rank
// at a time, rank 0 running one itself while its main thread hands the others theirs (it
// polls, so that it takes no core from its own run). Every rank calls it; rank 0's list is
// the one that counts. job(i) returns its answer for rank 0, never empty: rank 0 hears the
// other ranks' through on_answer(answer, rank), each on its main thread as the rank asks for
// its next job, and of each job it hands out through on_handed(job, rank). Rank 0's own jobs
// are not answered: what job(i) did there is done. A stop request (stop_requested) hands
// out no more jobs.
void run_jobs(std::vector<int> jobs, int workers, const MpiSession* mpi, const std::function<std::string(int job)>& job,
              const std::function<void(const std::string& answer, int rank)>& on_answer = {},
              const std::function<void(int job, int rank)>& on_handed = {});

}  // namespace ishibashi
