// The one threading seam of the engine. Kernels are plain loops over an index range;
// this decides how ranges are spread over OpenMP threads. Static contiguous chunks in
// thread order make every reduction that follows chunk order deterministic, and no
// chunking depends on the team size: a run may change it at any step (thread_tuner.h).
#pragma once
#include <omp.h>

#include <algorithm>
#include <cstddef>

namespace ishibashi {

// The team size of the parallel loops started from this thread; 0: OpenMP's (the
// --threads option, OMP_NUM_THREADS, or all cores). World::step sets it for its stages.
inline thread_local int team_size = 0;

inline int thread_count() { return team_size > 0 ? team_size : omp_get_max_threads(); }

// Sets this thread's team size for the lifetime of the object.
class ScopedTeamSize {
 public:
  explicit ScopedTeamSize(int threads) : saved_(team_size) { team_size = threads; }
  ~ScopedTeamSize() { team_size = saved_; }
  ScopedTeamSize(const ScopedTeamSize&) = delete;
  ScopedTeamSize& operator=(const ScopedTeamSize&) = delete;

 private:
  int saved_;
};

// Chunks of every sum over blocks or pairs: a fixed count, so that the partial sums are
// added in the same order whatever the number of threads.
constexpr int kReductionChunks = 64;

// Chunks of the loops that fill per-chunk buffers (broadphase candidates, re-clipped
// sub-contacts): a fixed count, so the buffers keep their capacity whatever the team size.
constexpr int kBufferChunks = 64;

// Below this many items (blocks or pairs) a loop runs on the calling thread: waking a
// team costs more than a tiny scene's whole step, and a descheduled thread on a busy
// machine would stall it.
constexpr std::ptrdiff_t kMinParallelItems = 128;

// Calls fn(i) for i in [0, n), spread over the threads.
template <class Fn>
void parallel_for(std::ptrdiff_t n, Fn&& fn) {
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (n >= kMinParallelItems)
  for (std::ptrdiff_t i = 0; i < n; ++i) fn(i);
}

// Calls fn(begin, end, chunk) for `chunk_count` contiguous chunks covering [0, n), chunk k
// before chunk k+1 in index order. The chunking depends on chunk_count only, never on
// the number of threads, so per-chunk results can be combined deterministically.
template <class Fn>
void parallel_chunks(std::ptrdiff_t n, int chunk_count, Fn&& fn) {
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (n >= kMinParallelItems)
  for (int k = 0; k < chunk_count; ++k) {
    const std::ptrdiff_t begin = n * k / chunk_count;
    const std::ptrdiff_t end = n * (k + 1) / chunk_count;
    fn(begin, end, k);
  }
}

}  // namespace ishibashi
