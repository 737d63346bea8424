// Usable cores against fake /proc and /sys trees: a cgroup's CPU quota (v2 and v1, on the
// group or an ancestor) caps the thread count below the CPUs OpenMP sees.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdlib>
#include <fstream>

#include "engine/cores.h"
#include "command_line.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

TEST(Cores, QuotaRoundsUpToWholeCores) {
  EXPECT_EQ(cores_in_quota(200000, 100000), 2);
  EXPECT_EQ(cores_in_quota(150000, 100000), 2);
  EXPECT_EQ(cores_in_quota(10000, 100000), 1);
  EXPECT_EQ(cores_in_quota(-1, 100000), 0);  // v1: no quota
  EXPECT_EQ(cores_in_quota(100000, 0), 0);
}

TEST(Cores, CgroupV2QuotaOfTheGroupOrAnAncestorCapsTheCount) {
  const int procs = omp_get_num_procs();
  const fs::path root = test::tmp_dir() / "cores_v2";
  fs::remove_all(root);
  write(root / "proc/self/cgroup", "0::/user.slice/job\n");
  write(root / "sys/fs/cgroup/user.slice/job/cpu.max", "max 100000\n");
  EXPECT_EQ(usable_cores(root), procs);  // no quota anywhere
  write(root / "sys/fs/cgroup/user.slice/cpu.max", "100000 100000\n");
  EXPECT_EQ(usable_cores(root), 1);  // the parent's one core
  write(root / "sys/fs/cgroup/user.slice/cpu.max", "max 100000\n");
  write(root / "sys/fs/cgroup/cpu.max", "100000 50000\n");  // a container's own root group
  EXPECT_EQ(usable_cores(root), std::min(procs, 2));
}

TEST(Cores, CgroupV1QuotaCapsTheCount) {
  const int procs = omp_get_num_procs();
  const fs::path root = test::tmp_dir() / "cores_v1";
  fs::remove_all(root);
  write(root / "proc/self/cgroup", "7:memory:/docker/abc\n4:cpu,cpuacct:/docker/abc\n");
  write(root / "sys/fs/cgroup/cpu,cpuacct/docker/abc/cpu.cfs_quota_us", "-1\n");
  write(root / "sys/fs/cgroup/cpu,cpuacct/docker/abc/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(usable_cores(root), procs);
  write(root / "sys/fs/cgroup/cpu,cpuacct/docker/abc/cpu.cfs_quota_us", "100000\n");
  EXPECT_EQ(usable_cores(root), 1);
}

TEST(Cores, ThisMachineHasAtLeastOneAndAtMostItsCpus) {
  const int n = usable_cores();
  EXPECT_GE(n, 1);
  EXPECT_LE(n, omp_get_num_procs());
}

// The one decision of a thread count: a request as given, else OMP_NUM_THREADS, else the
// usable cores, shared among the jobs running at once, never below one.
TEST(Cores, ThreadCountIsTheRequestElseTheEnvironmentElseTheCoresSharedByJobs) {
  const char* saved = std::getenv("OMP_NUM_THREADS");
  const std::string saved_value = saved ? saved : "";
  unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(decide_thread_count(3), 3);
  EXPECT_EQ(decide_thread_count(3, 8), 3);  // a request is per job already
  EXPECT_EQ(decide_thread_count(0), usable_cores());
  EXPECT_EQ(decide_thread_count(0, 2), std::max(1, usable_cores() / 2));
  EXPECT_EQ(decide_thread_count(0, 1000), 1);
  setenv("OMP_NUM_THREADS", "6", 1);
  EXPECT_EQ(decide_thread_count(0), 6);
  EXPECT_EQ(decide_thread_count(0, 2), 3);
  EXPECT_EQ(decide_thread_count(5, 2), 5);
  EXPECT_EQ(use_threads(0, 3), 2);
  EXPECT_EQ(omp_get_max_threads(), 2);
  setenv("OMP_NUM_THREADS", "not a number", 1);
  EXPECT_EQ(decide_thread_count(0), usable_cores());
  if (saved) setenv("OMP_NUM_THREADS", saved_value.c_str(), 1);
  else unsetenv("OMP_NUM_THREADS");
}

}  // namespace
}  // namespace ishibashi
