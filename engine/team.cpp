#include "engine/team.h"

#include <algorithm>

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

// The fields of a claim word (Slot::range) and of the loop's shape word (Team::shape_).
std::uint32_t generation_of(std::uint64_t word) { return static_cast<std::uint32_t>(word >> 32); }
// A claim word's chunks taken from the range's start (by its owner) and from its end (by
// the others).
int from_start_of(std::uint64_t range) { return static_cast<int>(range >> 16 & 0xFFFF); }
int from_end_of(std::uint64_t range) { return static_cast<int>(range & 0xFFFF); }
int threads_of(std::uint64_t shape) { return static_cast<int>(shape >> 16 & 0xFFFF); }
int count_of(std::uint64_t shape) { return static_cast<int>(shape & 0xFFFF); }

// Range r of a loop of `count` chunks on `threads` threads: chunks [begin, end).
int range_begin(int r, int count, int threads) { return static_cast<int>(std::int64_t{count} * r / threads); }

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

void Team::clear_times(int threads) {
  for (int i = 0; i < std::min(threads, kMaxThreads); ++i) slots_[i].time = ThreadTime{};
}

void Team::run(int threads, int chunk_count, ChunkFn chunk, const void* context) {
  threads = std::min(threads, kMaxThreads);
  if (threads <= 1 || chunk_count <= 1 || chunk_count > kMaxChunks || inside_loop) {
    const double begin = timing_ && !inside_loop ? now_s() : 0;
    for (int k = 0; k < chunk_count; ++k) chunk(context, k);
    if (timing_ && !inside_loop && chunk_count > 0) note_time(0, begin, true, chunk_count, false);
    return;
  }
  const int workers = threads - 1;
  while (static_cast<int>(workers_.size()) < workers)
    workers_.emplace_back(&Team::worker_loop, this, static_cast<int>(workers_.size()));
  if (active_workers_.load() != workers) {
    active_workers_.store(workers);
    active_workers_.notify_all();
  }

  // The ranges' claim words are not reset here: each is a cache line its owner's claims
  // left in its own core (on 16 threads, 15 lines to fetch before the loop could start,
  // and each owner's first claim fetched its own back). A claim that finds an older
  // loop's word starts the range afresh (claim()). Only every 2^30 loops are they all
  // reset, so that no word falls 2^31 loops behind, where the generations' comparison wraps.
  if (++generation_ % (1u << 30) == 0)
    for (Slot& slot : slots_) slot.range.store(std::uint64_t{generation_} << 32, std::memory_order_relaxed);
  // Relaxed: posted_'s store publishes them (the workers read it with acquire), and is
  // the one full fence of a posting (then sleepers_ is read: see wait_for_loop).
  chunk_.store(chunk, std::memory_order_relaxed);
  context_.store(context, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  shape_.store(std::uint64_t{generation_} << 32 | std::uint64_t(threads) << 16 | std::uint64_t(chunk_count),
               std::memory_order_relaxed);
  posted_.store(generation_);
  if (sleepers_.load() > 0) posted_.notify_all();

  inside_loop = true;
  run_chunks(0, generation_);
  inside_loop = false;
  const double wait_begin = timing_ ? now_s() : 0;
  wait_for_chunks(chunk_count);
  if (timing_) slots_[0].time.wait_s += now_s() - wait_begin;
}

void Team::wait_for_chunks(int chunk_count) {
  // Only chunks other threads have claimed and not finished are left: wait for them.
  const auto all_done = [&] { return done_.load(std::memory_order_acquire) == chunk_count; };
  if (spin_until(all_done)) return;
  caller_asleep_.store(true);  // then reads done_; a worker adds to done_, then reads this
  for (int done = done_.load(); done != chunk_count; done = done_.load()) done_.wait(done);
  caller_asleep_.store(false);
}

int Team::claim(int r, std::uint32_t generation, int size, bool from_end) {
  std::atomic<std::uint64_t>& range = slots_[r].range;
  std::uint64_t seen = range.load(std::memory_order_relaxed);
  for (;;) {
    const std::int32_t behind = static_cast<std::int32_t>(generation - generation_of(seen));
    if (behind < 0) return -1;  // a newer loop's: this one is done
    // An older loop's word: none of this loop's chunks of the range is claimed yet. A
    // thread still in a finished loop never gets here: that loop claimed a chunk of each
    // of its ranges but an empty one, so their words are of that loop or newer.
    const std::uint64_t current = behind > 0 ? std::uint64_t{generation} << 32 : seen;
    const int start = from_start_of(current), end = from_end_of(current);
    if (start + end >= size) return -1;
    if (range.compare_exchange_weak(seen, current + (from_end ? 1 : std::uint64_t{1} << 16)))
      return from_end ? size - 1 - end : start;
  }
}

int Team::run_chunks(int me, std::uint32_t generation) {
  const std::uint64_t shape = shape_.load();
  if (generation_of(shape) != generation) return 0;  // a newer loop is posted: this one is done
  const int threads = threads_of(shape), count = count_of(shape);
  const ChunkFn chunk = chunk_.load();
  const void* context = context_.load();
  const double begin = timing_ ? now_s() : 0;
  int ran = 0, reported = 0;
  // Its own range first, then the others' in turn from the next thread's.
  for (int step = 0; step < threads; ++step) {
    const int r = (me + step) % threads;
    const int begin_r = range_begin(r, count, threads), size = range_begin(r + 1, count, threads) - begin_r;
    for (int k; (k = claim(r, generation, size, step > 0)) >= 0; ++ran) chunk(context, begin_r + k);
    if (ran > reported) {
      if (timing_) note_time(me, begin, reported == 0, ran - reported, step > 0);  // before done_: the caller reads it after
      const int total = done_.fetch_add(ran - reported) + ran - reported;
      if (caller_asleep_.load()) done_.notify_one();
      reported = ran;
      if (total == count) break;
    } else if (step == 0 && done_.load() == count) {
      break;  // nothing of its own left and every chunk done: no need to read the others' claims
    }
  }
  return ran;
}

void Team::note_time(int me, double begin_s, bool first_report, int chunks, bool stolen) {
  ThreadTime& t = slots_[me].time;
  t.chunks += chunks;
  if (stolen) t.stolen += chunks;
  const double end = now_s();
  const double from = first_report ? begin_s : t.end_s;  // a later report extends the loop's share
  if (first_report && t.loops++ == 0) t.begin_s = begin_s;
  t.busy_s += end - from;
  t.end_s = end;
}

bool Team::wait_for_loop(int index, std::uint32_t seen) {
  for (;;) {
    if (stop_.load()) return false;
    const int active = active_workers_.load();
    if (index >= active) {  // not in the team now: sleep until its size changes
      active_workers_.wait(active);
      continue;
    }
    // posted_ has a line of its own: the spinning does not slow the claims of a loop still
    // running on the others.
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
  while (wait_for_loop(index, seen)) {
    seen = posted_.load();
    run_chunks(index + 1, seen);
  }
}

}  // namespace ishibashi
