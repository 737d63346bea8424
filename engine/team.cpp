#include "engine/team.h"

#include <algorithm>
#include <chrono>

namespace ishibashi {
namespace {

// True on a worker, and on a caller while its loop runs.
thread_local bool inside_loop = false;

// A waiting thread spins through the short gaps between a step's loops, then sleeps: a
// sleeping thread leaves its core idle, and the kernel moves a team mate that another
// process has pushed off its own core there at once (spinning or yielding keeps the core
// busy, and the team mate waits for a scheduler slice).
constexpr std::chrono::microseconds kSpin{200};

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Spins until ready() or kSpin has passed; returns ready().
template <class Ready>
bool spin_until(Ready&& ready) {
  const auto give_up = std::chrono::steady_clock::now() + kSpin;
  for (int i = 1;; ++i) {
    if (ready()) return true;
    pause();
    if (i % 64 == 0 && std::chrono::steady_clock::now() > give_up) return ready();
  }
}

// The fields of the loop word (Team::loop_).
std::uint32_t generation_of(std::uint64_t loop) { return static_cast<std::uint32_t>(loop >> 32); }
int count_of(std::uint64_t loop) { return static_cast<int>(loop >> 20 & 0xFFF); }
int next_of(std::uint64_t loop) { return static_cast<int>(loop & 0xFFFFF); }

}  // namespace

Team& Team::of_this_thread() {
  thread_local Team team;
  return team;
}

Team::~Team() {
  stop_.store(true);
  posted_.fetch_add(1);  // wakes every waiter: the values they wait on change
  posted_.notify_all();
  active_workers_.fetch_add(1);
  active_workers_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void Team::run(int threads, int chunk_count, ChunkFn chunk, const void* context) {
  if (threads <= 1 || chunk_count <= 1 || chunk_count > kMaxChunks || inside_loop) {
    for (int k = 0; k < chunk_count; ++k) chunk(context, k);
    return;
  }
  const int workers = threads - 1;
  while (static_cast<int>(workers_.size()) < workers)
    workers_.emplace_back(&Team::worker_loop, this, static_cast<int>(workers_.size()));
  if (active_workers_.load() != workers) {
    active_workers_.store(workers);
    active_workers_.notify_all();
  }

  chunk_.store(chunk);
  context_.store(context);
  done_.store(0);
  ++generation_;
  loop_.store(std::uint64_t{generation_} << 32 | std::uint64_t(chunk_count) << 20);
  posted_.store(generation_);
  if (sleepers_.load() > 0) posted_.notify_all();

  inside_loop = true;
  run_chunks();
  inside_loop = false;
  // Only chunks other threads have claimed and not finished are left: wait for them.
  const auto all_done = [&] { return done_.load(std::memory_order_acquire) == chunk_count; };
  if (spin_until(all_done)) return;
  caller_asleep_.store(true);  // then reads done_; a worker adds to done_, then reads this
  for (int done = done_.load(); done != chunk_count; done = done_.load()) done_.wait(done);
  caller_asleep_.store(false);
}

std::uint32_t Team::run_chunks() {
  int done = 0;
  for (;;) {
    // Guided claims: a share of what is left, so that few claims cross between cores and
    // the last chunks still spread over the team.
    const std::uint64_t seen = loop_.load(std::memory_order_relaxed);
    const int left = std::max(0, count_of(seen) - next_of(seen));
    const int batch = std::max(1, left / (active_workers_.load(std::memory_order_relaxed) + 1));
    const std::uint64_t loop = loop_.fetch_add(batch);
    const int k = next_of(loop), count = count_of(loop);
    if (k >= count) {
      if (done > 0) {  // once per thread and loop: the counter's cache line moves little
        done_.fetch_add(done);
        if (caller_asleep_.load()) done_.notify_one();
      }
      return generation_of(loop);
    }
    // The loop cannot be replaced before these chunks are counted done, so these are its own.
    const ChunkFn chunk = chunk_.load();
    const void* context = context_.load();
    const int end = std::min(k + batch, count);
    for (int j = k; j < end; ++j) chunk(context, j);
    done += end - k;
  }
}

bool Team::wait_for_loop(int index, std::uint32_t seen) {
  for (;;) {
    if (stop_.load()) return false;
    const int active = active_workers_.load();
    if (index >= active) {  // not in the team now: sleep until its size changes
      active_workers_.wait(active);
      continue;
    }
    // posted_ (stored just after loop_) has a line of its own: the spinning does not slow
    // the claims of a loop still running on the others.
    const auto posted = [&] { return stop_.load() || posted_.load() != seen; };
    if (spin_until(posted)) return !stop_.load();
    // Sleep. The caller stores posted_ before it reads sleepers_, this thread counts
    // itself before it reads posted_: one of the two sees the other.
    sleepers_.fetch_add(1);
    for (std::uint32_t p = posted_.load(); !posted() && index < active_workers_.load(); p = posted_.load())
      posted_.wait(p);
    sleepers_.fetch_sub(1);
  }
}

void Team::worker_loop(int index) {
  inside_loop = true;
  std::uint32_t seen = 0;
  while (wait_for_loop(index, seen)) seen = run_chunks();
}

}  // namespace ishibashi
