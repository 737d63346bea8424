// The worker threads behind the step's parallel loops (parallel.h). A loop's chunks are cut
// into one contiguous range per thread, the same from one loop to the next: thread i (the
// caller is 0) claims the chunks of range i in order, so a stage's data stays in the
// cache of the core that used it last step (model F: about 14 MB of sub-contact state).
// A thread that has finished its range takes chunks from the ends of the others' ranges,
// the next thread's first, while each owner works from its range's start (Box2D v3's
// solver stages do likewise): the chunks a lagging thread loses are its range's last, the
// same from step to step while the same thread lags, so they too stay in one cache.
// A loop ends when its chunks are done, not when every thread has arrived: a thread the
// scheduler has taken off its core (another process busy on the machine) misses the loop
// instead of holding it up, and the others do its range. OpenMP's loops end at a barrier
// that waits for every thread, a scheduler slice each time one is descheduled: a fixed
// team of two beside one busy core ran 4 to 100 times slower (issue 28, lever 4).
//
// Which thread runs a chunk never changes what the chunk computes (chunks write their own
// slots), so results do not depend on the team. No heap allocation after the workers
// start; atomics only to post a loop, claim its chunks and count them done (none on forces).
//
// With timing on (run --profile, --trace), each thread notes when it began and ended its
// share of each loop and how long it worked (ThreadTime), for World::step to sum per stage.
#pragma once
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "engine/cores.h"

namespace ishibashi {

// One thread's share of the loops since the last Team::clear_times: seconds on the team's
// clock (Team::now_s). Zero loops: it ran no chunk.
struct ThreadTime {
  double busy_s = 0;   // from its first claim to its last chunk's end, summed over loops
  double begin_s = 0;  // its first loop's first claim
  double end_s = 0;    // its last loop's last chunk's end
  double wait_s = 0;   // the caller: waiting for the others' last chunks
  int loops = 0;       // loops in which it ran at least one chunk
  int chunks = 0;      // chunks it ran
  int stolen = 0;      // of them, chunks of another thread's range
};

class Team {
 public:
  using ChunkFn = void (*)(const void* context, int chunk);
  static constexpr int kMaxChunks = 1024;  // < 2^16: a range's claim counts are 16-bit fields
  static constexpr int kMaxThreads = ishibashi::kMaxThreads;

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

  // Tests: as if the loops up to `posted` had been posted, each claim word last reset at
  // it (the caller's own reset every 2^30 loops), so that a test reaches the loop count's
  // wrap at 2^32 without running four billion loops. Only between loops.
  void skip_to_loop_for_test(std::uint32_t posted) {
    generation_ = posted;
    for (Slot& slot : slots_) slot.range.store(std::uint64_t{posted} << 32, std::memory_order_relaxed);
  }

  // Timing of each thread's share of the loops (off by default: two clock reads per
  // thread and loop when on).
  void set_timing(bool on) { timing_ = on; }
  bool timing() const { return timing_; }
  void clear_times(int threads);
  const ThreadTime& time_of(int thread) const { return slots_[thread].time; }
  double now_s() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - epoch_).count(); }

 private:
  void worker_loop(int index);
  // Claims and runs chunks of loop `generation` as thread `me`: its own range, then the
  // others'. Returns how many it ran.
  int run_chunks(int me, std::uint32_t generation);
  // Claims the next of the `size` chunks of range r of loop `generation`, its owner from
  // the range's start, the others (from_end) from its end: its index in the range, -1 when
  // none is left.
  int claim(int r, std::uint32_t generation, int size, bool from_end);
  // The caller, after its own chunks: until every chunk of the posted loop is done.
  void wait_for_chunks(int chunk_count);
  // Notes thread me's share of the loop that it began at begin_s, as of now, and the
  // `chunks` it ran since its last note (`stolen`: from another thread's range).
  void note_time(int me, double begin_s, bool first_report, int chunks, bool stolen);
  // Waits until a loop newer than `seen` is posted; false when the team stops.
  bool wait_for_loop(int index, std::uint32_t seen);

  // Per thread, a cache line of its own: the claim word of its range (generation << 32 |
  // chunks taken from its start << 16 | from its end; a word of an older loop counts as
  // none taken, one of a newer loop as none left: a finished loop's worker claims nothing)
  // and its timing.
  struct alignas(64) Slot {
    std::atomic<std::uint64_t> range{0};
    ThreadTime time;
  };

  std::vector<std::thread> workers_;
  std::uint32_t generation_ = 0;  // the caller's count of posted loops
  std::array<Slot, kMaxThreads> slots_;
  alignas(64) std::atomic<int> done_{0};  // chunks of the posted loop finished
  alignas(64) std::atomic<std::uint32_t> posted_{0};  // the generation, stored last
  alignas(64) std::atomic<ChunkFn> chunk_{nullptr};
  std::atomic<const void*> context_{nullptr};
  // The posted loop's generation << 32 | threads << 16 | chunk count, in one word so that a
  // worker reads a consistent shape (its claims then match only that loop's ranges).
  std::atomic<std::uint64_t> shape_{0};
  std::atomic<int> sleepers_{0};               // workers asleep on posted_
  std::atomic<bool> caller_asleep_{false};     // the caller sleeps on done_
  std::atomic<int> active_workers_{0};         // workers 0 .. active-1 take part: the team size - 1
  std::atomic<bool> stop_{false};
  bool timing_ = false;
  const std::chrono::steady_clock::time_point epoch_ = std::chrono::steady_clock::now();
};

}  // namespace ishibashi
