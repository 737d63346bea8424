// The chaos probe (analysis/batch/chaos_probe.h): where the strong motion begins (Arias
// intensity against hand arithmetic); a problem that is not chaotic, a block sliding to
// rest on a slab under a pulse, keeps its members within 1e-6 m of the reference; under
// mpirun its runs are the same as on one machine; the position series counts a row written
// again after a resume once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/batch/chaos_probe.h"
#include "command_line.h"
#include "io/ground_motion.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, state_hash_of, box_off_file, kMpirunTwoRanks, kRoot, tmp_dir
namespace fs = std::filesystem;

TEST(ChaosProbe, StrongMotionBeginsAtFivePerCentOfTheAriasIntensity) {
  // a for 1 s, then 2a for 1 s, then nothing: the intensity grows as a^2 t, then 4 a^2 t,
  // 5 a^2 in all. 5 % (0.25 a^2) is reached at 0.25 s, 50 % (2.5 a^2) at 1 + 1.5 / 4 s.
  GroundMotion g;
  g.dt_s = 1e-3;
  for (int k = 0; k < 3000; ++k) {
    const double a = k < 1000 ? 3.0 : 0.0, two_a = k >= 1000 && k < 2000 ? -6.0 : 0.0;
    g.accel_m_s2.push_back(Vec3(a, two_a, 9.0));
  }
  EXPECT_NEAR(arias_time_s(g, 0.05), 0.25, 2e-3);
  EXPECT_NEAR(arias_time_s(g, 0.5), 1.375, 2e-3);
  EXPECT_NEAR(arias_time_s(g, 1.0), 1.999, 2e-3);  // the vertical component does not count
}

// A 1 x 1 x 0.3 m stone on a fixed slab, the ground pulsed in x at 1 g for 0.2 s and then
// at -0.5 g for 0.4 s, to rest (friction 0.655: the stone slips about 9 cm in the first
// pulse and sticks in the second; with a base three times its height it cannot tip).
fs::path sliding_block_scenario() {
  const fs::path model = tmp_dir() / "probe_sliding_block.toml";
  std::ofstream(model) << "[import]\nfiles = [\"" << box_off_file(tmp_dir() / "probe_stone.off", {1.5, 1.5, 0.5}, {1, 1, 0.3}).string()
                       << "\"]\nfixed_files = [\"" << box_off_file(tmp_dir() / "probe_slab.off", {0, 0, 0}, {4, 4, 0.5}).string() << "\"]\n";
  const fs::path record = tmp_dir() / "probe_pulse.txt";
  std::ofstream pulse(record);
  for (int k = 0; k < 100; ++k) pulse << (k >= 20 && k < 40 ? 1.0 : k >= 40 && k < 80 ? -0.5 : 0.0) << '\n';
  const fs::path scenario = tmp_dir() / "probe_sliding.toml";
  std::ofstream(scenario) << "[model]\nfile = \"" << model.string() << "\"\n"
                          << "[run]\nsettle_max_s = 0.1\nduration_s = 0.9\noutput_interval_s = 0.02\nthreads = 1\n"
                          << "dt_s = 2.5e-5\n"  // (0.7 of the stability limit) divides the frames and the settling's checks
                          << "[ground_motion]\nbaseline_correction = false\n"
                          << "x = { file = \"" << record.string() << "\", format = \"columns\", unit = \"g\", dt_s = 0.01 }\n";
  return scenario;
}

TEST(ChaosProbe, BlockSlidingToRestKeepsItsMembersTogether) {
  const fs::path out = tmp_dir() / "probe_sliding";
  fs::remove_all(out);
  int status = 0;
  const std::string printed = run_command(test::program() + " run " + sliding_block_scenario().string() +
                                              " --probe 3 --perturbation 1e-7 --branch-at 0.1 --out " + out.string(),
                                          &status);
  ASSERT_EQ(status, 0) << printed;
  const nlohmann::json probe = nlohmann::json::parse(text_of(out / "probe.json"));
  ASSERT_EQ(probe["finished"].get<int>(), 3) << printed;
  EXPECT_NEAR(probe["branch_shaking_s"].get<double>(), 0.1, 1e-12);
  // The branch stops at its frame at 0.1 s of shaking (frames 0.02 s apart, on the step's
  // multiples: settling ends at a check, 0.05 s), not at the next.
  EXPECT_NEAR(nlohmann::json::parse(text_of(out / "branch" / "summary.json"))["shaking_time_s"].get<double>(), 0.1, 1e-9);
  const PositionSeries reference = read_positions(out / "member_000" / "positions.bin");
  ASSERT_GT(reference.time_s.size(), 40u);
  ASSERT_EQ(reference.blocks, 2u);
  const int stone = reference.centroid[0][2] > reference.centroid[0][5] ? 0 : 1, slab = 1 - stone;
  auto slip = [&](const PositionSeries& s, std::size_t row) {
    return s.centroid[row][3 * stone] - s.centroid[row][3 * slab] - (s.centroid[0][3 * stone] - s.centroid[0][3 * slab]);
  };
  // The stone slid as Coulomb's law has it, and came to rest: in the first pulse the slab
  // outruns it by (g - mu g) 0.2^2 / 2 = 0.0677 m, reaching (g - mu g) 0.2 = 0.677 m/s
  // relative; in the second they close at (0.5 g + mu g) = 11.33 m/s^2, 0.0202 m more.
  const std::size_t last = reference.time_s.size() - 1;
  EXPECT_NEAR(slip(reference, last), -0.0879, 0.004);
  EXPECT_NEAR(slip(reference, last), slip(reference, last - 5), 1e-6);
  for (int member : {1, 2}) {
    const PositionSeries s = read_positions(out / ("member_00" + std::to_string(member)) / "positions.bin");
    ASSERT_EQ(s.time_s.size(), reference.time_s.size());
    // Moved by the perturbation at the branch, exactly; within 1e-6 m of the reference after.
    EXPECT_NEAR((Eigen::Map<const Vec3>(&s.centroid[0][3 * stone]) - Eigen::Map<const Vec3>(&reference.centroid[0][3 * stone])).norm(),
                1e-7, 1e-12);
    EXPECT_LE(probe["parting"][member - 1]["largest_separation_m"].get<double>(), 1e-6) << member;
    EXPECT_TRUE(probe["parting"][member - 1]["parted_0.1_mm_s"].is_null());
  }
  const std::string csv = text_of(out / "probe.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "shaking_time_s,member_1_separation_m,member_2_separation_m");
  EXPECT_NE(text_of(out / "members.csv").find("\n2,1e-07,"), std::string::npos) << text_of(out / "members.csv");

  // Again: every run is current and kept.
  const std::string again = run_command(test::program() + " run " + sliding_block_scenario().string() +
                                            " --probe 3 --perturbation 1e-7 --branch-at 0.1 --out " + out.string(),
                                        &status);
  EXPECT_EQ(status, 0) << again;
  EXPECT_NE(again.find("branch: current, kept"), std::string::npos) << again;
  EXPECT_NE(again.find("member 2: current, kept"), std::string::npos) << again;
}

// Under mpirun the branch runs on one rank and the members across both, each the same run,
// bit for bit, as on one machine; rank 0 alone writes the tables and reports.
TEST(ChaosProbe, MpirunRanksRunTheSameMembersAsOneMachine) {
  const fs::path local = tmp_dir() / "probe_mpi_local", ranks = tmp_dir() / "probe_mpi_ranks";
  fs::remove_all(local);
  fs::remove_all(ranks);
  const std::string probe =
      test::program() + " run " + sliding_block_scenario().string() + " --probe 3 --perturbation 1e-7 --branch-at 0.1 --out ";
  int status = 0;
  const std::string one = run_command(probe + local.string() + " --jobs 2", &status);
  ASSERT_EQ(status, 0) << one;
  const std::string two = run_command(kMpirunTwoRanks + probe + ranks.string(), &status);
  ASSERT_EQ(status, 0) << two;
  EXPECT_EQ(count_of(two, "branch (rank 0): started") + count_of(two, "branch (rank 1): started"), 1)
      << "the branch runs once: " << two;
  EXPECT_GE(count_of(two, "(rank 1): done"), 1) << "rank 1 ran no member: " << two;
  EXPECT_EQ(count_of(two, "chaos probe: 3 members"), 1) << "only rank 0 reports the probe: " << two;
  for (const char* run : {"branch", "member_000", "member_001", "member_002"}) {
    ASSERT_FALSE(state_hash_of(local / run).empty()) << run;
    EXPECT_EQ(state_hash_of(ranks / run), state_hash_of(local / run)) << run;
  }
  EXPECT_EQ(text_of(ranks / "probe.csv"), text_of(local / "probe.csv"));
}

// A member's folder holds no checkpoint but its own, written after its nudge: a member
// stopped before its first checkpoint (a killed process) starts again from the branch,
// perturbed. (With the branch's checkpoint copied in among its files, such a member went
// on from it unperturbed, a copy of the reference: model B dry's member 2, session 40.)
// A probe compares its members to the record's end: one asked to stop them at a collapse is
// refused with the setting that would run it, before any member runs.
TEST(ChaosProbe, StopAtCollapseIsRefused) {
  const fs::path out = tmp_dir() / "probe_stop_at";
  fs::remove_all(out);
  int status = 0;
  const std::string printed = run_command(test::program() + " run " + sliding_block_scenario().string() +
                                              " --probe 2 --stop-at collapse --out " + out.string(),
                                          &status);
  EXPECT_NE(status, 0) << printed;
  EXPECT_NE(printed.find("stop_at = \"collapse\": a chaos probe follows its members to the record's end"), std::string::npos)
      << printed;
  EXPECT_NE(printed.find("(--stop-at end)"), std::string::npos) << printed;
  EXPECT_FALSE(fs::exists(out / "member_000"));
}

TEST(ChaosProbe, AMemberStoppedBeforeItsFirstCheckpointStartsAgainPerturbed) {
  const fs::path out = tmp_dir() / "probe_restart";
  fs::remove_all(out);
  ChaosProbeOptions o;
  o.out = out;
  o.members = 2;
  o.perturbation_m = 1e-7;
  o.branch_at_s = 0.1;
  int starts = 0;
  o.on_event = [&](const std::string& line) {
    if (line != "member 1: started") return;
    ++starts;  // where a killed process leaves the folder: no checkpoint yet
    EXPECT_FALSE(fs::exists(out / "member_001" / "checkpoint.bin"));
  };
  const Scenario sc = read_scenario(sliding_block_scenario());
  ASSERT_EQ(run_chaos_probe(sc, o).finished, 2);
  auto moved_at_branch = [&] {
    const PositionSeries reference = read_positions(out / "member_000" / "positions.bin");
    const PositionSeries member = read_positions(out / "member_001" / "positions.bin");
    double largest = 0;
    for (std::size_t i = 0; i < reference.centroid[0].size(); i += 3)
      largest = std::max(largest, (Eigen::Map<const Vec3>(&member.centroid[0][i]) - Eigen::Map<const Vec3>(&reference.centroid[0][i])).norm());
    return largest;
  };
  EXPECT_NEAR(moved_at_branch(), 1e-7, 1e-12);

  // Member 1 as a kill before its first checkpoint leaves it: started, not finished.
  fs::remove(out / "member_001" / "inputs.key");
  ASSERT_EQ(run_chaos_probe(sc, o).finished, 2);
  EXPECT_EQ(starts, 2);
  EXPECT_NEAR(moved_at_branch(), 1e-7, 1e-12);
}

TEST(ChaosProbe, PositionRowsWrittenAgainAfterAResumeCountOnce) {
  const fs::path f = tmp_dir() / "probe_positions.bin";
  {
    std::ofstream out(f, std::ios::binary);
    const std::uint64_t blocks = 1;
    out.write("ISBPOS01", 8).write(reinterpret_cast<const char*>(&blocks), 8);
    // Rows at 0, 1, 2; a resume from the checkpoint at 1 writes 2 and 3 again; a stop cuts the last row short.
    for (double t : {0.0, 1.0, 2.0, 2.0, 3.0}) {
      const double row[4] = {t, 10 * t, 0, 0};
      out.write(reinterpret_cast<const char*>(row), sizeof row);
    }
    out.write("\0\0\0\0\0\0\0\0\0\0\0\0", 12);
  }
  const PositionSeries s = read_positions(f);
  ASSERT_EQ(s.time_s, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(s.centroid[3][0], 30.0);
  std::ofstream(f) << "not positions";
  EXPECT_THROW(read_positions(f), InputError);
}

// A member resumed after a stop (or a full disk) cut its last row short appends after the
// whole rows, not after the cut one, which would shift every later row by its bytes.
TEST(ChaosProbe, RowAppendedAfterARowCutShortStartsOnARowBoundary) {
  const fs::path f = tmp_dir() / "probe_positions_cut.bin";
  fs::remove(f);
  State s;
  s.position = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  for (double t : {0.0, 1.0}) {
    s.time_s = t;
    append_positions(f, s);
  }
  fs::resize_file(f, fs::file_size(f) - 20);  // the row at 1 s cut short
  s.time_s = 2.0;
  s.position[1] = Vec3(7, 8, 9);
  append_positions(f, s);
  const PositionSeries series = read_positions(f);
  ASSERT_EQ(series.time_s, (std::vector<double>{0, 2}));
  EXPECT_EQ(series.centroid[1], (std::vector<double>{1, 2, 3, 7, 8, 9}));
  fs::resize_file(f, 10);  // even the header cut short: the file starts again
  append_positions(f, s);
  EXPECT_EQ(read_positions(f).time_s, std::vector<double>{2});
}

}  // namespace
}  // namespace ishibashi
