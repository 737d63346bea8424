// The one threading seam of the engine. Kernels are plain loops over an index range;
// this decides how ranges are spread over the threads of the caller's team (team.h).
// Chunks are contiguous and fixed by the loop alone, and every reduction that follows
// adds per-chunk results in chunk order: no result depends on which thread ran a chunk,
// nor on the team size, which a run may change at any step (thread_tuner.h).
#pragma once
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>

#include "engine/team.h"

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

// Chunks of the step's long loops over blocks (pose with the broadphase check, gather) and, by
// their first block, pairs (narrowphase, contact law): one per kStageChunkBlocks blocks,
// at most kStageChunks. Model F (2,003 blocks) gets 250: on 16 threads about 16 each, so a
// thread that ends its range early takes work in pieces of 1/250 of the stage (with 64
// such a piece was a fifth of a 16-thread stage and the team waited for it: 20 % of the
// contact law's team time); model A (166 blocks) 20, so that claiming a chunk stays
// cheap against running it. Fixed by the model, never by the threads; the contact law's
// and gather's per-chunk energy sums are added in chunk order.
constexpr int kStageChunks = 256;
constexpr int kStageChunkBlocks = 8;
inline int stage_chunks(std::ptrdiff_t blocks) {
  return static_cast<int>(std::clamp<std::ptrdiff_t>(blocks / kStageChunkBlocks, 1, kStageChunks));
}

// Below this many items (blocks or pairs) a loop runs on the calling thread: waking a
// team costs more than a tiny scene's whole step.
constexpr std::ptrdiff_t kMinParallelItems = 128;

// Runs chunk(k), k < chunk_count, on the caller's team, or on the calling thread alone
// when the loop covers fewer than kMinParallelItems items. An exception in a chunk (an
// allocation failing as a cracked bridge's buffers grow) is caught where it was thrown,
// the loop's other chunks run on (they may use this frame), and the caller rethrows it
// once the loop is done: the program's own handler then says what happened, where
// std::terminate would have ended it with the runtime's line. The first thread to catch
// one keeps it; its flag costs a relaxed load a loop.
template <class Chunk>
void run_on_team(std::ptrdiff_t items, int chunk_count, const Chunk& chunk) {
  struct Loop {
    const Chunk& chunk;
    std::atomic<bool> failed{false};
    std::exception_ptr error;  // written by the thread that set `failed`
  } loop{chunk, {false}, {}};
  const int threads = items >= kMinParallelItems ? thread_count() : 1;
  Team::of_this_thread().run(
      threads, chunk_count,
      [](const void* context, int k) noexcept {
        auto& l = *static_cast<Loop*>(const_cast<void*>(context));
        try {
          l.chunk(k);
        } catch (...) {
          if (!l.failed.exchange(true)) l.error = std::current_exception();
        }
      },
      &loop);
  if (loop.failed.load(std::memory_order_relaxed)) std::rethrow_exception(loop.error);
}

// Calls fn(begin, end, chunk) for `chunk_count` contiguous chunks covering [0, n), chunk k
// before chunk k+1 in index order. The chunking depends on chunk_count only, never on
// the number of threads, so per-chunk results can be combined deterministically.
template <class Fn>
void parallel_chunks(std::ptrdiff_t n, int chunk_count, Fn&& fn) {
  run_on_team(n, chunk_count, [&](int k) { fn(n * k / chunk_count, n * (k + 1) / chunk_count, k); });
}

// Calls fn(begin, end, chunk) for the chunks [bounds[k], bounds[k + 1]), k < chunk_count
// (bounds non-decreasing, chunk_count + 1 of them): chunks of uneven length, fixed by the
// data alone (State::pair_chunk_begin), never by the number of threads.
template <class Fn>
void parallel_ranges(const int* bounds, int chunk_count, Fn&& fn) {
  run_on_team(bounds[chunk_count] - bounds[0], chunk_count,
              [&](int k) { fn(std::ptrdiff_t{bounds[k]}, std::ptrdiff_t{bounds[k + 1]}, k); });
}

// Calls fn(i) for i in [0, n) (blocks), spread over the threads.
template <class Fn>
void parallel_for(std::ptrdiff_t n, Fn&& fn) {
  parallel_chunks(n, stage_chunks(n), [&](std::ptrdiff_t begin, std::ptrdiff_t end, int) {
    for (std::ptrdiff_t i = begin; i < end; ++i) fn(i);
  });
}

}  // namespace ishibashi
