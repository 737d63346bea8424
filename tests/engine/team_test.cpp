// The team behind the parallel loops (engine/team.h): every chunk runs once whatever the
// team does, workers take part, a loop inside a chunk runs inline, a team stops with its
// thread, the chunks taken from another's range are counted, and a loop does not wait for
// a worker that is held off its core.
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <new>
#include <thread>
#include <vector>

#include "engine/parallel.h"

namespace ishibashi {
namespace {

// Runs fn(k) for every chunk k of one loop on a team of `threads`.
template <class Fn>
void run_loop(int threads, int chunk_count, Fn&& fn) {
  using F = std::remove_reference_t<Fn>;
  Team::of_this_thread().run(
      threads, chunk_count, [](const void* c, int k) { (*static_cast<const F*>(c))(k); }, &fn);
}

TEST(Team, EveryChunkRunsOnceWhateverTheTeam) {
  std::vector<std::atomic<int>> runs(Team::kMaxChunks + 1);
  const int chunk_counts[] = {1, 2, 7, 64, 1000, Team::kMaxChunks, Team::kMaxChunks + 1};
  for (int loop = 0; loop < 3500; ++loop) {
    const int threads = 1 + loop % 4, chunks = chunk_counts[loop % 7];
    for (int k = 0; k < chunks; ++k) runs[k] = 0;
    run_loop(threads, chunks, [&](int k) { runs[k].fetch_add(1); });
    for (int k = 0; k < chunks; ++k) ASSERT_EQ(runs[k].load(), 1) << "loop " << loop << ", chunk " << k;
  }
}

// A loop's posting leaves the claim words alone: a claim starts an older loop's word
// afresh, and every 2^30 loops the caller resets them all, so that the generations'
// comparison (modulo 2^32) never meets a word 2^31 loops behind. Across those resets and
// the count's wrap, with the team shrinking and growing (its idle ranges' words left
// behind) and loops with fewer chunks than threads (empty ranges), every chunk still
// runs once.
TEST(Team, EveryChunkRunsOnceWhereTheLoopCountWraps) {
  Team team;
  std::vector<std::atomic<int>> runs(64);
  auto loop = [&](int threads, int chunks) {
    for (int k = 0; k < chunks; ++k) runs[k] = 0;
    auto fn = [&](int k) { runs[k].fetch_add(1); };
    team.run(threads, chunks, [](const void* c, int k) { (*static_cast<const decltype(fn)*>(c))(k); }, &fn);
    for (int k = 0; k < chunks; ++k) ASSERT_EQ(runs[k].load(), 1) << threads << " threads, chunk " << k;
  };
  const int chunk_counts[] = {64, 3, 1, 17};
  for (const std::uint64_t boundary : {1ull << 30, 1ull << 31, 3ull << 30, 1ull << 32}) {
    team.skip_to_loop_for_test(static_cast<std::uint32_t>(boundary - 40));
    for (int i = 0; i < 80; ++i) loop(i < 20 || i >= 60 ? 4 : 2, chunk_counts[i % 4]);
  }
}

// The chunks sleep, so a worker gets some even on one core.
std::vector<pthread_t> threads_of_a_sleepy_loop(int threads) {
  std::vector<pthread_t> who(16);
  run_loop(threads, 16, [&](int k) {
    who[k] = pthread_self();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  return who;
}

// An allocation failing in a chunk (a cracked bridge's buffers growing) reaches the
// caller as the exception it was, after the loop's other chunks ran, on any team, and the
// team runs the next loop as usual. It used to end the program (std::terminate).
TEST(Team, AnExceptionInAChunkReachesTheCallerAfterTheLoop) {
  for (int threads : {1, 2, 4}) {
    const ScopedTeamSize team(threads);
    std::vector<std::atomic<int>> runs(64);
    EXPECT_THROW(parallel_chunks(6400, 64,
                                 [&](std::ptrdiff_t, std::ptrdiff_t, int k) {
                                   runs[k].fetch_add(1);
                                   if (k == 13 || k == 50) throw std::bad_alloc();
                                 }),
                 std::bad_alloc);
    for (int k = 0; k < 64; ++k) EXPECT_EQ(runs[k].load(), 1) << threads << " threads, chunk " << k;
    std::atomic<int> next{0};
    parallel_chunks(6400, 64, [&](std::ptrdiff_t, std::ptrdiff_t, int) { next.fetch_add(1); });
    EXPECT_EQ(next.load(), 64) << threads;
  }
}

TEST(Team, WorkersTakePart) {
  int on_workers = 0;
  for (pthread_t t : threads_of_a_sleepy_loop(2)) on_workers += !pthread_equal(t, pthread_self());
  EXPECT_GT(on_workers, 0);
  EXPECT_LT(on_workers, 16);
}

TEST(Team, ALoopInsideAChunkRunsInline) {
  std::vector<int> inner_on_its_thread(64, 0);
  run_loop(2, 64, [&](int k) {
    const pthread_t outer = pthread_self();
    int same = 0;
    parallel_chunks(1000, 8, [&](std::ptrdiff_t, std::ptrdiff_t, int) { same += pthread_equal(pthread_self(), outer); });
    inner_on_its_thread[k] = same;
  });
  for (int same : inner_on_its_thread) EXPECT_EQ(same, 8);
}

TEST(Team, StopsWithItsThread) {
  std::atomic<int> chunks{0};
  std::thread caller([&] { run_loop(4, 64, [&](int) { chunks.fetch_add(1); }); });
  caller.join();  // the thread's team joins its workers as the thread exits
  EXPECT_EQ(chunks.load(), 64);
}

// With timing on (run --profile), each thread counts the chunks it ran and those it took
// from another thread's range: here the caller's range (chunks 0-3 of 8 on two threads)
// holds the caller in its first chunk until the worker, its own range done, has taken one.
// On a busy machine the caller may start late and the worker take chunk 0 itself: it counts.
TEST(Team, TimingCountsTheChunksTakenFromAnotherThreadsRange) {
  Team& team = Team::of_this_thread();
  team.set_timing(true);
  team.clear_times(2);
  const pthread_t caller = pthread_self();
  std::atomic<int> taken_by_worker{0};
  run_loop(2, 8, [&](int k) {
    const bool on_caller = pthread_equal(pthread_self(), caller);
    if (k < 4 && !on_caller) taken_by_worker.fetch_add(1);
    if (k == 0 && on_caller) {
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      while (taken_by_worker == 0 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    }
  });
  team.set_timing(false);
  ASSERT_GT(taken_by_worker.load(), 0) << "the worker took none of the caller's chunks in 5 s";
  EXPECT_EQ(team.time_of(0).chunks + team.time_of(1).chunks, 8);
  EXPECT_EQ(team.time_of(1).stolen, taken_by_worker.load());
  EXPECT_EQ(team.time_of(1).chunks, 4 + taken_by_worker.load());
  EXPECT_EQ(team.time_of(0).stolen, 0);
}

std::atomic<bool> held{false};
void hold_this_thread(int) {  // async-signal-safe: an atomic store and nanosleep
  held = true;
  const timespec half_second{0, 500'000'000};
  nanosleep(&half_second, nullptr);
}

// A worker the scheduler keeps off its core (held here in a signal handler for 0.5 s)
// misses the loops instead of holding them up: a barrier on every thread would wait.
TEST(Team, LoopsDoNotWaitForAWorkerHeldOffItsCore) {
  pthread_t worker{};
  for (pthread_t t : threads_of_a_sleepy_loop(2))
    if (!pthread_equal(t, pthread_self())) worker = t;
  ASSERT_FALSE(pthread_equal(worker, pthread_t{})) << "no chunk ran on the worker";

  struct sigaction action {}, previous{};
  action.sa_handler = hold_this_thread;
  sigaction(SIGUSR1, &action, &previous);
  held = false;
  pthread_kill(worker, SIGUSR1);
  while (!held) std::this_thread::yield();

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<double> sums(64);
  for (int loop = 0; loop < 100; ++loop) run_loop(2, 64, [&](int k) { sums[k] += k; });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 0.25) << "the loops waited for the held worker";
  for (int k = 0; k < 64; ++k) EXPECT_EQ(sums[k], 100.0 * k);

  threads_of_a_sleepy_loop(2);  // the worker is back and takes part again
  sigaction(SIGUSR1, &previous, nullptr);
}

}  // namespace
}  // namespace ishibashi
