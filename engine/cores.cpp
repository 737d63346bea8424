#include "engine/cores.h"

#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace ishibashi {
namespace {

// The tightest quota on the path from `group` (inside the hierarchy mounted at `mount`) up
// to the mount point: a child group never gets more than its parents allow.
int tightest_quota(const std::filesystem::path& mount, std::filesystem::path group, bool v2) {
  int cores = 0;
  for (;;) {
    const std::filesystem::path dir = mount / group.relative_path();
    long long quota = 0, period = 0;
    if (v2) {
      std::ifstream in(dir / "cpu.max");  // "max 100000" or "200000 100000"
      std::string q;
      if (in >> q >> period && q != "max") quota = std::atoll(q.c_str());
    } else {
      std::ifstream(dir / "cpu.cfs_quota_us") >> quota;
      std::ifstream(dir / "cpu.cfs_period_us") >> period;
    }
    const int here = cores_in_quota(quota, period);
    if (here > 0) cores = cores > 0 ? std::min(cores, here) : here;
    if (!group.has_relative_path()) return cores;
    group = group.parent_path();
  }
}

}  // namespace

int cores_in_quota(long long quota_us, long long period_us) {
  if (quota_us <= 0 || period_us <= 0) return 0;
  return static_cast<int>(std::max(1LL, (quota_us + period_us - 1) / period_us));
}

int usable_cores(const std::filesystem::path& root) {
  int cores = std::max(1, omp_get_num_procs());
  // /proc/self/cgroup: "0::/path" (v2) or "4:cpu,cpuacct:/path" (v1), one line per hierarchy.
  std::ifstream groups(root / "proc/self/cgroup");
  std::string line;
  while (std::getline(groups, line)) {
    const auto first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::filesystem::path group = line.substr(second + 1);
    int quota = 0;
    if (controllers.empty()) {
      quota = tightest_quota(root / "sys/fs/cgroup", group, true);
    } else {
      std::stringstream list(controllers);
      std::string c;
      while (std::getline(list, c, ','))
        if (c == "cpu") quota = tightest_quota(root / "sys/fs/cgroup" / controllers, group, false);
    }
    if (quota > 0) cores = std::min(cores, quota);
  }
  return cores;
}

int decide_thread_count(int requested, int jobs) {
  if (requested > 0) return requested;
  int available = usable_cores();
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (const int from_env = env ? std::atoi(env) : 0; from_env > 0) available = from_env;
  return std::max(1, available / std::max(1, jobs));
}

int use_threads(int requested, int jobs) {
  const int threads = decide_thread_count(requested, jobs);
  omp_set_num_threads(threads);
  return threads;
}

}  // namespace ishibashi
