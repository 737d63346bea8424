// `ishibashi sweep` end to end on model A with short records: the rows, the IDA and
// fragility outputs; the same rows under `mpirun -np 2` as on one machine; a sweep killed
// half-way resumes without redoing its finished runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include "command_line.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, kRoot, tmp_dir

// The rows of sweep.csv without the wall time and host (they differ between machines),
// sorted (runs finish in any order).
std::vector<std::string> rows(const std::filesystem::path& out) {
  std::ifstream in(out / "sweep.csv");
  std::vector<std::string> result;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) result.push_back(line.substr(0, line.rfind(',', line.rfind(',') - 1)));
  std::sort(result.begin(), result.end());
  return result;
}

// Model A, 0.1 s of shaking, two records (the Kobe record's horizontal components
// swapped), scale factors 0.5 and 1: four runs.
std::filesystem::path sweep_file() {
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  const auto scenario = tmp_dir() / "ishibashi_sweep_scenario.toml";
  std::ofstream(scenario) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\n"
                          << "[run]\nsettle_max_s = 0.1\nduration_s = 0.1\noutput_interval_s = 0.05\n"
                          << "[ground_motion]\nx = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n";
  const auto file = tmp_dir() / "ishibashi_sweep.toml";
  const std::string ew = (kobe / "RSN1106_KOBE_KJM090.AT2").string(), ns = (kobe / "RSN1106_KOBE_KJM000.AT2").string(),
                    up = (kobe / "RSN1106_KOBE_KJM-UP.AT2").string();
  std::ofstream(file) << "[sweep]\nscenario = \"" << scenario.string() << "\"\nscale = [0.5, 1.0]\n"
                      << "[failure]\ncollapse = true\ncrown_drop_m = 1e-5\n"
                      << "[[record]]\nname = \"kobe_ew_ns\"\nstart_s = 7.6\nx = { file = \"" << ew << "\" }\ny = { file = \""
                      << ns << "\" }\nz = { file = \"" << up << "\" }\n"
                      << "[[record]]\nname = \"kobe_ns_ew\"\nstart_s = 7.6\nx = { file = \"" << ns << "\" }\ny = { file = \""
                      << ew << "\" }\nz = { file = \"" << up << "\" }\n";
  return file;
}

const std::string kSweep = std::string(ISHIBASHI_BINARY) + " sweep ";

TEST(Sweep, OneMachineAndMpirunGiveTheSameRows) {
  const auto file = sweep_file();
  const auto local = tmp_dir() / "ishibashi_sweep_local", mpi = tmp_dir() / "ishibashi_sweep_mpi";
  std::filesystem::remove_all(local);
  std::filesystem::remove_all(mpi);
  int status = 0;
  const std::string one = run_command(kSweep + file.string() + " --jobs 2 --threads-per-job 1 --out " + local.string(), &status);
  ASSERT_EQ(status, 0) << one;
  EXPECT_EQ(count_of(one, ": done (rank 0)"), 4) << one;
  ASSERT_EQ(rows(local).size(), 4u);
  for (const char* output : {"ida.csv", "fragility.csv", "fragility_fit.csv", "ida.png", "fragility.png"})
    EXPECT_TRUE(std::filesystem::exists(local / output)) << output;
  EXPECT_TRUE(std::filesystem::exists(local / "runs/kobe_ns_ew_0.5/blocks.pvd"));

  const std::string launcher = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 2 ";
  const std::string two = run_command(launcher + kSweep + file.string() + " --threads-per-job 1 --out " + mpi.string(), &status);
  ASSERT_EQ(status, 0) << two;
  EXPECT_NE(two.find("2 MPI ranks"), std::string::npos) << two;
  EXPECT_EQ(count_of(two, ": done (rank"), 4) << two;
  EXPECT_GE(count_of(two, ": done (rank 1)"), 1) << "rank 1 took no run: " << two;
  EXPECT_EQ(rows(mpi), rows(local));
}

TEST(Sweep, KilledSweepResumesWithoutRedoingFinishedRuns) {
  const auto file = sweep_file();
  const auto out = tmp_dir() / "ishibashi_sweep_killed";
  std::filesystem::remove_all(out);
  int status = 0;
  // SIGKILL as soon as the first row is in sweep.csv: the second run is under way.
  const std::string sweep = kSweep + file.string() + " --jobs 1 --threads-per-job 2 --out " + out.string();
  const std::string table = (out / "sweep.csv").string();
  run_command("bash -c '" + sweep + " & pid=$!; until [ -f " + table + " ] && [ $(wc -l < " + table +
                  ") -ge 2 ]; do sleep 0.05; done; kill -KILL $pid'",
              &status);
  const std::size_t before = rows(out).size();
  ASSERT_GE(before, 1u);
  ASSERT_LT(before, 4u) << "the sweep finished before it was killed";
  const std::string resumed = run_command(sweep, &status);
  ASSERT_EQ(status, 0) << resumed;
  EXPECT_NE(resumed.find(std::to_string(before) + " done before"), std::string::npos) << resumed;
  EXPECT_EQ(count_of(resumed, ": done (rank 0)"), static_cast<int>(4 - before)) << resumed;
  EXPECT_EQ(rows(out).size(), 4u);
}

}  // namespace
}  // namespace ishibashi
