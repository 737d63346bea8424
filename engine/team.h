// The worker threads behind the step's parallel loops (parallel.h). A loop is cut into a
// fixed number of chunks that the threads claim a few at a time, and it ends when its chunks
// are done, not when every thread has arrived: a thread the scheduler has taken off its
// core (another process busy on the machine) misses the loop instead of holding it up, and
// the others do its chunks. OpenMP's loops end at a barrier that waits for every thread,
// a scheduler slice each time one is descheduled: a fixed team of two beside one busy core
// ran 4 to 100 times slower (issue 28, lever 4).
//
// Which thread runs a chunk never changes what the chunk computes (chunks write their own
// slots), so results do not depend on the team. No heap allocation after the workers
// start; atomics only to post a loop, claim its chunks and count them done (none on forces).
#pragma once
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace ishibashi {

class Team {
 public:
  using ChunkFn = void (*)(const void* context, int chunk);
  static constexpr int kMaxChunks = 4095;

  // The team of the calling thread: its workers start on first use and stop when the
  // thread exits (each `study --jobs` job has its own).
  static Team& of_this_thread();

  Team() = default;
  ~Team();
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;

  // Calls chunk(context, k) for every k in [0, chunk_count) on the calling thread and up
  // to threads - 1 workers (more than kMaxChunks chunks, or a loop started inside a
  // chunk: on the calling thread alone, no nested teams, as OpenMP's default); returns
  // when all have returned.
  void run(int threads, int chunk_count, ChunkFn chunk, const void* context);

 private:
  void worker_loop(int index);
  // Claims and runs chunks of the posted loop until none is left; returns its generation.
  std::uint32_t run_chunks();
  // Waits until a loop newer than `seen` is posted; false when the team stops.
  bool wait_for_loop(int index, std::uint32_t seen);

  std::vector<std::thread> workers_;
  std::uint32_t generation_ = 0;  // the caller's count of posted loops
  // The posted loop: generation << 32 | chunk_count << 20 | next unclaimed chunk. Claims
  // are fetch_adds on it, so a late worker can only claim chunks of the loop now posted.
  // The counters written by every claim have a cache line each.
  alignas(64) std::atomic<std::uint64_t> loop_{0};
  alignas(64) std::atomic<int> done_{0};  // chunks of the posted loop finished
  alignas(64) std::atomic<std::uint32_t> posted_{0};  // the generation, for waiting workers
  alignas(64) std::atomic<ChunkFn> chunk_{nullptr};
  std::atomic<const void*> context_{nullptr};
  std::atomic<int> sleepers_{0};               // workers asleep on posted_
  std::atomic<bool> caller_asleep_{false};     // the caller sleeps on done_
  std::atomic<int> active_workers_{0};         // workers 0 .. active-1 take part: the team size - 1
  std::atomic<bool> stop_{false};
};

}  // namespace ishibashi
