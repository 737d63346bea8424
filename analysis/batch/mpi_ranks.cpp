#include "analysis/batch/mpi_ranks.h"

#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "analysis/batch/job_queue.h"

namespace ishibashi {
namespace {

constexpr int kAnswerTag = 1, kJobTag = 2;  // rank -> rank 0: the last job's answer; rank 0 -> rank: the next job

// Rank 0's main thread: hands the jobs of `queue` to the other ranks as they ask, until each
// has been told that none is left.
void serve_other_ranks(JobQueue& queue, const MpiSession& mpi,
                       const std::function<void(const std::string&, int)>& on_answer,
                       const std::function<void(int, int)>& on_handed) {
  for (int remote = mpi.size() - 1; remote > 0;) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kAnswerTag, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    std::string answer(static_cast<std::size_t>(length), '\0');
    MPI_Recv(answer.data(), length, MPI_CHAR, status.MPI_SOURCE, kAnswerTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (!answer.empty() && on_answer) on_answer(answer, status.MPI_SOURCE);  // empty: the rank's first request
    const int next = queue.take();
    if (next >= 0 && on_handed) on_handed(next, status.MPI_SOURCE);
    MPI_Send(&next, 1, MPI_INT, status.MPI_SOURCE, kJobTag, MPI_COMM_WORLD);
    if (next < 0) --remote;
  }
}

// Any other rank: asks rank 0 for a job, runs it and sends its answer with the next
// request, until rank 0 has none left. It waits for rank 0's reply by polling, as rank 0
// does: a blocking receive spins (Open MPI's default), and a rank may wait as long as a
// run takes (a chaos probe's branch, or the last jobs of a set of runs), on a core that the
// node's working ranks share.
void work_for_rank_zero(const std::function<std::string(int)>& job) {
  std::string answer;
  for (;;) {
    MPI_Send(answer.data(), static_cast<int>(answer.size()), MPI_CHAR, 0, kAnswerTag, MPI_COMM_WORLD);
    int next = -1, arrived = 0;
    MPI_Request reply;
    MPI_Irecv(&next, 1, MPI_INT, 0, kJobTag, MPI_COMM_WORLD, &reply);
    for (MPI_Test(&reply, &arrived, MPI_STATUS_IGNORE); !arrived; MPI_Test(&reply, &arrived, MPI_STATUS_IGNORE))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (next < 0) return;
    answer = job(next);
  }
}

}  // namespace

MpiSession::MpiSession() {
  active_ = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_RANK") || std::getenv("PMIX_RANK");
  if (!active_) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);  // MPI only on the main thread
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &local_size_);
  MPI_Comm_free(&node);
}

MpiSession::~MpiSession() {
  if (!active_) return;
  // A rank whose jobs ended waits here for the others' by polling: MPI_Finalize's own wait
  // spins, on a core the node's working ranks share, for as long as their last runs take.
  MPI_Request all_done;
  MPI_Ibarrier(MPI_COMM_WORLD, &all_done);
  for (int done = 0; MPI_Test(&all_done, &done, MPI_STATUS_IGNORE), !done;)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  MPI_Finalize();
}

void run_jobs(std::vector<int> jobs, int workers, const MpiSession* mpi, const std::function<std::string(int)>& job,
              const std::function<void(const std::string&, int)>& on_answer,
              const std::function<void(int, int)>& on_handed) {
  JobQueue queue(std::move(jobs));
  auto here = [&job](int i) { job(i); };
  if (!mpi || mpi->size() <= 1) {
    queue.start(workers - 1, here);
    queue.work(here);
  } else if (mpi->rank() != 0) {
    work_for_rank_zero(job);
  } else {
    queue.start(1, here);
    serve_other_ranks(queue, *mpi, on_answer, on_handed);
  }
  queue.join();
}

}  // namespace ishibashi
