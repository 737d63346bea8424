// The seismic run called as a function, as the study calls it: the same result on 1, 2
// and 4 threads, and two runs at once in one process (a study's jobs) change nothing.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <thread>

#include "analysis/run/seismic_run.h"

namespace ishibashi {
namespace {

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;

// A model through the strongest Kobe pulses (from 7.6 s of the record): model A settles
// for 0.1 s and is shaken for 0.2 s.
Scenario strong_pulses(int threads, const char* model = "nishida_a", double settle_s = 0.1, double shake_s = 0.2) {
  const auto f = std::filesystem::temp_directory_path() / (std::string("ishibashi_analysis_") + model + ".toml");
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  std::ofstream(f) << "[model]\nfile = \"" << (kRoot / "models" / (std::string(model) + ".toml")).string() << "\"\n"
                   << "[run]\nsettle_max_s = " << settle_s << "\nduration_s = " << shake_s << "\noutput_interval_s = 0.05\n"
                   << "[ground_motion]\nstart_s = 7.6\n"
                   << "x = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n"
                   << "y = { file = \"" << (kobe / "RSN1106_KOBE_KJM000.AT2").string() << "\" }\n"
                   << "z = { file = \"" << (kobe / "RSN1106_KOBE_KJM-UP.AT2").string() << "\" }\n";
  Scenario sc = read_scenario(f);
  sc.settings.threads = threads;
  return sc;
}

SeismicRunResult run_into(const std::string& folder, const Scenario& scenario) {
  const auto out = std::filesystem::temp_directory_path() / folder;
  std::filesystem::remove_all(out);
  SeismicRunOptions options;
  options.out = out;
  options.adaptive_threads = false;
  SeismicRun run(scenario, options);
  return run.run();
}

SeismicRunResult run_into(const std::string& folder, int threads) { return run_into(folder, strong_pulses(threads)); }

void expect_identical(const SeismicRunResult& a, const SeismicRunResult& b, const std::string& what) {
  EXPECT_EQ(a.state_hash, b.state_hash) << what;
  EXPECT_EQ(std::memcmp(&a.balance_error_j, &b.balance_error_j, sizeof(double)), 0) << what;
  EXPECT_EQ(a.steps, b.steps) << what;
  EXPECT_EQ(a.joint_counts.cracked, b.joint_counts.cracked) << what;
  EXPECT_EQ(a.fallen_stones, b.fallen_stones) << what;
}

TEST(SeismicRun, BridgeRunIsBitIdenticalOnOneTwoAndFourThreadsAndBesideAnotherRun) {
  const SeismicRunResult one = run_into("ishibashi_analysis_1", 1);
  EXPECT_GT(one.steps, 10000);
  EXPECT_LT(std::abs(one.balance_error_relative), 0.01);
  expect_identical(one, run_into("ishibashi_analysis_2", 2), "2 threads");
  expect_identical(one, run_into("ishibashi_analysis_4", 4), "4 threads");
  // Two runs at once on two threads of this process, as `ishibashi study --jobs 2` runs them.
  // (The scenarios are read first: both runs reading the file while it is rewritten would race.)
  const Scenario on_one = strong_pulses(1), on_two = strong_pulses(2);
  SeismicRunResult left, right;
  std::thread other([&] { right = run_into("ishibashi_analysis_right", on_one); });
  left = run_into("ishibashi_analysis_left", on_two);
  other.join();
  expect_identical(one, left, "beside another run, 2 threads");
  expect_identical(one, right, "beside another run, 1 thread");
}

// Model B (1,000 blocks: walls and a stone fill on the ring), 0.02 s settling and 0.02 s
// of the strongest pulses: the same state on 1 and 3 threads (chunks split unlike the 2 and
// 4 of the test above; the engine's tests compare 1 to 4 threads on smaller scenes). (Runs
// one after another in one process leave nothing behind: the test above runs model A five
// times.)
TEST(SeismicRun, ModelBIsBitIdenticalOnOneAndThreeThreads) {
  const SeismicRunResult one = run_into("ishibashi_analysis_b1", strong_pulses(1, "nishida_b", 0.02, 0.02));
  EXPECT_GT(one.joints, 1000);
  expect_identical(one, run_into("ishibashi_analysis_b3", strong_pulses(3, "nishida_b", 0.02, 0.02)), "3 threads");
}

}  // namespace
}  // namespace ishibashi
