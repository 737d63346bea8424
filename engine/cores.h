// How many cores this process may use: the CPUs it may run on (its affinity mask, what
// OpenMP counts) and, below that, the CPU time its control group allows. A container
// started with `docker run --cpus=2` on a 64-core host sees 64 CPUs but gets two cores'
// worth of time; 64 threads there spend the run waiting for each other's chunks.
#pragma once
#include <filesystem>

namespace ishibashi {

// Whole cores in a CFS quota of quota_us per period_us (rounded up); 0: no quota
// (quota_us <= 0, as cgroup v2's "max" or v1's -1).
int cores_in_quota(long long quota_us, long long period_us);

// min(omp_get_num_procs(), the tightest CPU quota of this process's cgroup and its
// ancestors; cgroup v2 cpu.max, or v1 cpu.cfs_quota_us / cpu.cfs_period_us). `root` is
// the file-system root holding proc/ and sys/ (a fake tree in the tests).
int usable_cores(const std::filesystem::path& root = "/");

// The largest team a run's loops use (engine/team.h): more threads than this is a typo.
constexpr int kMaxThreads = 256;

// The one decision of how many threads an analysis runs on. `requested` > 0 (a --threads
// option, a scenario's [run] threads, a study's threads per job) is taken as given;
// otherwise OMP_NUM_THREADS when it is set, else every usable core, shared among `jobs`
// analyses running at once; at least 1.
int decide_thread_count(int requested, int jobs = 1);

// Sets the threads of the parallel loops the calling thread starts (a World takes them
// when it is built) to decide_thread_count(requested, jobs); returns that count.
int use_threads(int requested, int jobs = 1);

}  // namespace ishibashi
