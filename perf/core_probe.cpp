// Are a machine's cores 0 and 1 cores of their own, and how far apart? (issue 47)
//   build/perf/core_probe
// A compute-bound loop and a streaming sum on one core, then on cores 0 and 1 at once
// (two cores of their own give 2x the throughput of one), and a cache line bounced
// between them (its round trip: what data the two threads of a step share costs).
//   build/perf/core_probe clock 1 2 4 8 16
// How fast one core computes while N cores compute at once (cores 0..N-1, the same loop,
// no data shared): a core that runs slower as more are busy (a lower turbo clock, a
// host's power budget, shared physical cores) makes N threads' work grow by that factor
// whatever the engine does, so the engine's own scaling is read against it.
//   build/perf/core_probe loops 1 2 4 8 16
// What one of the step's parallel loops costs the team beyond its chunks' work: loops of
// near-empty chunks (250: model F's stage loops; 64: the solve's sums) on N threads, the
// engine's own team (engine/team.h). A step runs 4-5 such loops with explicit dashpots and
// about 20 with implicit ones: their posting, claiming and ending is the step's cost that
// no chunk does.
#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "engine/parallel.h"

namespace {

void pin(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

volatile double sink;  // keeps the loops' results alive

// 64 independent multiply-add chains: enough to keep a core's floating-point units full.
long compute_rounds = 100'000'000;
void compute(int cpu) {
  pin(cpu);
  double acc[64];
  for (int k = 0; k < 64; ++k) acc[k] = 1.0 + k * 1e-3;
  for (long i = 0; i < compute_rounds; ++i)
    for (double& a : acc) a = a * 0.999999 + 1e-7;
  double sum = 0;
  for (double a : acc) sum += a;
  sink = sum;
}

// 128 MB a thread, read 100 times with eight integer sums: memory bandwidth, not latency.
std::vector<long> arrays[2];
void stream(int cpu) {
  pin(cpu);
  const std::vector<long>& v = arrays[cpu];
  long sums[8] = {};
  for (int round = 0; round < 100; ++round)
    for (std::size_t i = 0; i < v.size(); i += 8)
      for (int k = 0; k < 8; ++k) sums[k] += v[i + k];
  long sum = 0;
  for (long s : sums) sum += s;
  sink = static_cast<double>(sum);
}

template <class Work>
double seconds_of(Work work, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> team;
  for (int i = 0; i < threads; ++i) team.emplace_back(work, i);
  for (std::thread& t : team) t.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Round trip of one cache line between cores 0 and 1, ns.
double round_trip_ns() {
  alignas(64) static std::atomic<long> ball;
  const long trips = 2'000'000;
  ball = 0;
  auto play = [&](long first) {
    for (long i = first; i < 2 * trips; i += 2) {
      while (ball.load(std::memory_order_acquire) != i) {}
      ball.store(i + 1, std::memory_order_release);
    }
  };
  std::thread other([&] { pin(1); play(1); });
  pin(0);
  const auto t0 = std::chrono::steady_clock::now();
  play(0);
  other.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / trips * 1e9;
}

}  // namespace

// One line per count of cores: the compute loop's seconds on each of N cores at once,
// against the same loop on one core (1.00: as fast as alone), twice, one count after another.
int clock_scan(int argc, char** argv) {
  compute_rounds = 30'000'000;
  const unsigned cores = std::thread::hardware_concurrency();
  for (int round = 0; round < 2; ++round)
    for (int a = 2; a < argc; ++a) {
      const int n = std::atoi(argv[a]);
      if (n < 1 || unsigned(n) > cores) {
        std::fprintf(stderr, "core_probe clock: '%s' should be a count of cores from 1 to %u\n", argv[a], cores);
        return 1;
      }
      const double alone = seconds_of(compute, 1), together = seconds_of(compute, n);
      std::printf("clock: %2d busy at once, %.3f s each against %.3f s alone: each %.2fx slower\n", n, together,
                  alone, together / alone);
    }
  return 0;
}

// One line per count of threads and chunks: the median over batches of one loop's wall
// time on the calling thread, from its posting to its last chunk's end.
int loop_scan(int argc, char** argv) {
  const unsigned cores = std::thread::hardware_concurrency();
  struct alignas(64) Slot {
    long touched = 0;
  };
  static Slot slots[ishibashi::kStageChunks];
  for (int a = 2; a < argc; ++a) {
    const int n = std::atoi(argv[a]);
    if (n < 1 || unsigned(n) > cores) {
      std::fprintf(stderr, "core_probe loops: '%s' should be a count of threads from 1 to %u\n", argv[a], cores);
      return 1;
    }
    const ishibashi::ScopedTeamSize team(n);
    for (const int chunks : {250, 64}) {
      const int loops = 20'000, batches = 7;
      std::vector<double> us;
      for (int batch = 0; batch < batches; ++batch) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < loops; ++i)
          ishibashi::parallel_chunks(2003, chunks, [&](std::ptrdiff_t, std::ptrdiff_t, int k) { ++slots[k].touched; });
        us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / loops);
      }
      std::sort(us.begin(), us.end());
      std::printf("loops: %2d threads, %3d chunks: %.2f us a loop (median of %d batches of %d; %.2f-%.2f)\n", n, chunks,
                  us[batches / 2], batches, loops, us.front(), us.back());
    }
  }
  return 0;
}

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "clock") return clock_scan(argc, argv);
  if (argc > 1 && std::string(argv[1]) == "loops") return loop_scan(argc, argv);
  arrays[0].assign(16 << 20, 1);
  arrays[1].assign(16 << 20, 1);
  for (int round = 0; round < 2; ++round) {
    const double c1 = seconds_of(compute, 1), c2 = seconds_of(compute, 2);
    const double s1 = seconds_of(stream, 1), s2 = seconds_of(stream, 2);
    std::printf("compute: %.2f s on one core, %.2f s on two at once (%.2fx); stream: %.2f s, %.2f s (%.2fx); "
                "cache line round trip %.0f ns\n",
                c1, c2, 2 * c1 / c2, s1, s2, 2 * s1 / s2, round_trip_ns());
  }
}
