// Are a machine's cores 0 and 1 cores of their own, and how far apart? (issue 47)
//   build/perf/core_probe
// A compute-bound loop and a streaming sum on one core, then on cores 0 and 1 at once
// (two cores of their own give 2x the throughput of one), and a cache line bounced
// between them (its round trip: what data the two threads of a step share costs).
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace {

void pin(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

volatile double sink;  // keeps the loops' results alive

// 64 independent multiply-add chains: enough to keep a core's floating-point units full.
void compute(int cpu) {
  pin(cpu);
  double acc[64];
  for (int k = 0; k < 64; ++k) acc[k] = 1.0 + k * 1e-3;
  for (long i = 0; i < 100'000'000; ++i)
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

int main() {
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
