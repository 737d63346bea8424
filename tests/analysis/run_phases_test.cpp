// A seismic run's phases and what it measures against closed forms: settling ends at the
// first check (every kSettleCheckS) whose kinetic energy is below the threshold, bonds that
// break while settling are counted, a stone riding the ground neither drops nor moves
// relative to it, and a bridge's monitored block is its crown unit.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/model/compile_model.h"
#include "analysis/run/run_recorder.h"
#include "analysis/run/seismic_run.h"
#include "command_line.h"
#include "run_scenes.h"
#include "geometry/bridge.h"
#include "scenes.h"

namespace ishibashi {
namespace {

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;
using test::kG;

using test::history;
using test::run_into;
using test::scene;
using test::stone_and_slab;

// A lone stone in free fall (no other block: dt given) has the kinetic energy m (g t)^2 / 2
// after t seconds: 71.9 J at 0.05 s, 289 J at 0.1 s. Rest is judged every 0.05 s, not at
// every frame (0.01 s here, where the energy is 2.9 J, then 11.5 J): with the threshold a
// third of the energy at the first check the stone never rests and settles for as long as
// it may; at 1.5 times that energy it rests at the first check (0.05 s), also with frames
// 0.03 s apart that step over it; settling that ends between checks is judged at its end.
TEST(Settling, EndsAtTheFirstCheckWhoseKineticEnergyIsBelowTheThreshold) {
  const auto dir = test::tmp_dir() / "ishibashi_settling";
  std::filesystem::create_directories(dir);
  test::box_off_file(dir / "stone.off", {0, 0, 1}, {1, 1, 0.3});
  const std::string model = "[import]\nfiles = [\"" + (dir / "stone.off").string() + "\"]\n";
  const double mass = 600, at_check = 0.5 * mass * std::pow(kG * kSettleCheckS, 2);
  auto settle = [&](double settle_max_s, double interval_s, double threshold_j) {
    std::ostringstream run;
    run << "[run]\ndt_s = 1e-4\nthreads = 1\nduration_s = 0.002\nsettle_max_s = " << settle_max_s
        << "\noutput_interval_s = " << interval_s << "\nsettle_kinetic_j = " << threshold_j << "\n";
    return run_into(dir / "out", scene(dir, model, run.str(), {0, 0, 0, 0}));
  };
  const SeismicRunResult restless = settle(0.12, 0.01, at_check / 3);
  EXPECT_FALSE(restless.settled);
  EXPECT_NEAR(restless.settle_time_s, 0.12, 2e-4);
  for (double interval : {0.01, 0.03}) {
    const SeismicRunResult rests = settle(0.12, interval, 1.5 * at_check);
    EXPECT_TRUE(rests.settled) << "frames " << interval << " s apart";
    EXPECT_NEAR(rests.settle_time_s, kSettleCheckS, 2e-4) << "frames " << interval << " s apart";
  }
  // Settling that may last 0.03 s ends there and is judged then: 25.9 J.
  const SeismicRunResult short_settling = settle(0.03, 0.01, 1.5 * 0.5 * mass * std::pow(kG * 0.03, 2));
  EXPECT_TRUE(short_settling.settled);
  EXPECT_NEAR(short_settling.settle_time_s, 0.03, 2e-4);
}

// A stone held between two fixed walls only by its two bonded side joints (0.3 m^2 each)
// loads them in shear with its weight: 600 kg g / 0.6 m^2 = 9.8 kPa, up to twice that as
// the stone starts to sag. Mortar of 2 kPa breaks both joints while settling (the stone
// then slides down between the walls); mortar of 100 kPa holds, and none breaks.
TEST(Settling, BondsThatBreakWhileSettlingAreCounted) {
  const auto dir = test::tmp_dir() / "ishibashi_settling_bonds";
  std::filesystem::create_directories(dir);
  test::box_off_file(dir / "stone.off", {-0.5, -0.5, 0.85}, {1, 1, 0.3});
  test::box_off_file(dir / "left.off", {-1.5, -0.5, -0.25}, {1, 1, 1.5});
  test::box_off_file(dir / "right.off", {0.5, -0.5, -0.25}, {1, 1, 1.5});
  const std::string model = "[import]\nfiles = [\"" + (dir / "stone.off").string() + "\"]\nfixed_files = [\"" +
                            (dir / "left.off").string() + "\", \"" + (dir / "right.off").string() + "\"]\n";
  auto settle = [&](double mortar_pa) {
    std::ostringstream run;
    run << "mortar_pa = " << mortar_pa << "\nmortar_bonds = \"initial\"\n[run]\nthreads = 1\nsettle_max_s = 0.1\nduration_s = 0.002\n";
    return run_into(dir / "out", scene(dir, model, run.str(), {0, 0, 0, 0}));
  };
  const SeismicRunResult weak = settle(2e3);
  EXPECT_EQ(weak.joints, 2);
  EXPECT_EQ(weak.bonds_broken_settling, 2);
  const SeismicRunResult strong = settle(1e5);
  EXPECT_EQ(strong.bonds_broken_settling, 0);
  EXPECT_TRUE(strong.settled);
}

// A stone hung under a fixed slab by mortar (f_t = 9 kPa), without dashpots: released at
// rest, it sags towards twice its static pull (2 x 5.9 kPa) and the bond breaks on the way.
// Nothing but the broken springs' release (bond_j) leaves the stone's mechanical energy, so
// the balance closes as semi-implicit Euler does, to second order in dt: halving the step
// divides its error by about four (5.7 % of the release, then 0.85 % and 0.21 %). Released
// as its springs' energy at the step it broke, the error only halved (29 %, 12 %, 6.3 %).
TEST(Settling, ABrittleBondsBreakClosesTheEnergyBalanceToSecondOrderInDt) {
  const auto dir = test::tmp_dir() / "ishibashi_hung_stone";
  const std::string model = stone_and_slab(dir, 0.7, 1.0);
  const std::string run = "mortar_pa = 9000\nmortar_bonds = \"initial\"\n[run]\nthreads = 1\nsettle_max_s = 0.01\nduration_s = 0.002\n";
  const Scenario sc = scene(dir, model, run, {0, 0, 0, 0}, "x", "damping_normal = 0\ndamping_shear = 0\n");
  std::vector<double> error;
  for (double dt_factor : {0.5, 0.25, 0.125}) {
    SeismicRunOptions options;
    options.out = dir / "out";
    options.dt_factor = dt_factor;
    std::filesystem::remove_all(options.out);
    const SeismicRunResult r = SeismicRun(sc, options).run();
    EXPECT_EQ(r.bonds_broken_settling, 1) << dt_factor;
    error.push_back(std::abs(r.balance_error_relative));
  }
  EXPECT_GT(error[0] / error[1], 3.0);
  EXPECT_GT(error[1] / error[2], 3.0);
  EXPECT_LT(error[2], 0.01);
}

// A stone on a fixed slab, the ground moved up and down by a = -0.5 g sin(4 pi t) for half a
// second: the ground sinks by (a0/w) t - (a0/w^2) sin(w t), 0.195 m in all, and the stone
// (never lighter than half its weight) rides it. Its drop relative to the ground (the
// crown's drop of a bridge: here the monitored block) and its displacement relative to the
// ground in history.csv stay within its springs' give, a fraction of a micrometre.
TEST(RunMeasures, AStoneRidingTheGroundUpAndDownNeitherDropsNorMovesAgainstIt) {
  const auto dir = test::tmp_dir() / "ishibashi_riding";
  const std::string model = stone_and_slab(dir);
  const double a0 = 0.5 * kG, w = 4 * M_PI;
  std::vector<double> record;
  for (int k = 0; k <= 500; ++k) record.push_back(-0.5 * std::sin(w * k * 1e-3));
  const std::string run = "[run]\nthreads = 1\nsettle_max_s = 0.1\nduration_s = 0.5\noutput_interval_s = 0.05\n[monitor]\nblocks = [0]\n";
  const Scenario sc = scene(dir, model, run, record, "z");
  ASSERT_EQ(load_model(sc.model, sc.model_file, model_options(sc.settings)).motion[0], Motion::free) << "block 0 is the stone";
  const SeismicRunResult r = run_into(dir / "out", sc);
  ASSERT_TRUE(r.settled);
  EXPECT_NEAR(r.shaking_time_s, 0.5, 1e-3);
  auto columns = history(dir / "out");
  // The springs' give: the settled stone's sag under its weight (0.16 um); the ground's
  // pull varies its load between 0.5 and 1.5 times that weight.
  double sag = 0;
  int shaking_rows = 0;
  for (std::size_t k = 0; k < columns["time_s"].size(); ++k) {
    if (columns["phase"][k] == "settle") sag = -std::stod(columns["block0_dz_m"][k]);
    if (columns["phase"][k] != "shake") continue;
    ++shaking_rows;
    const double t = std::stod(columns["time_s"][k]) - r.settle_time_s;
    EXPECT_NEAR(std::stod(columns["ground_dz_m"][k]), -(a0 / w) * t + (a0 / (w * w)) * std::sin(w * t), 1e-4) << t << " s";
    EXPECT_NEAR(std::stod(columns["block0_dz_m"][k]), -sag, sag) << t << " s";
  }
  EXPECT_GE(shaking_rows, 10);
  EXPECT_GT(sag, 0);
  EXPECT_LT(sag, 1e-6);
  EXPECT_LT(r.largest_crown_drop_m, sag);
  std::ifstream summary(dir / "out" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(summary)["mean_team_size"].get<double>(), 1.0) << "threads = 1: one thread every step";
}

// A stone bonded on a slab (0.3 m thick: 600 kg/m^2 of its joint) whose ground drops ever
// faster, a = -5 g t: once the ground falls faster than g the joint pulls the stone down
// with sigma = 600 kg/m^2 (|a| - g), uniform over the joint (no moment: the pull is
// vertical). Mortar of f_t = 6 kPa parts when |a| = g + 10 m/s^2, at 0.404 s of shaking;
// the run reports its first opening then, in seconds of shaking (within the 50 steps
// between its looks), and the bond's utilisation reached 1 by then.
TEST(RunMeasures, ABondPulledByTheGroundOpensWhenItsTensionReachesTheStrength) {
  const auto dir = test::tmp_dir() / "ishibashi_pulled_bond";
  const std::string model = stone_and_slab(dir);
  std::vector<double> record;
  for (int k = 0; k <= 600; ++k) record.push_back(-5.0 * k * 1e-3);
  const std::string run = "mortar_pa = 6000\n[run]\nthreads = 1\nsettle_max_s = 0.1\nduration_s = 0.6\n";
  const SeismicRunResult r = run_into(dir / "out", scene(dir, model, run, record, "z"));
  ASSERT_TRUE(r.settled);
  const double opens_s = (kG + 6000.0 / 600.0) / (5 * kG);
  EXPECT_NEAR(r.first_opening_s, opens_s, 0.005);
  EXPECT_GT(r.bond_utilisation_peak, 0.95);
  EXPECT_LE(r.bond_utilisation_peak, 1.0);
}

// A run asked for a checkpoint every 0.02 s of simulated time, its frames 0.01 s apart,
// writes one at every other frame (the frames are where it may), counted by the file's
// changes between the frames' callbacks (each called before its frame's checkpoint).
TEST(RunMeasures, ACheckpointIsWrittenEveryCheckpointIntervalOfSimulatedTime) {
  const auto dir = test::tmp_dir() / "ishibashi_checkpoint_cadence";
  const std::string model = stone_and_slab(dir);
  const std::string run = "[run]\nthreads = 1\nsettle_max_s = 0.1\nduration_s = 0.1\noutput_interval_s = 0.01\n";
  const Scenario sc = scene(dir, model, run, std::vector<double>(200, 0.0));
  SeismicRunOptions options;
  options.out = dir / "out";
  options.checkpoint_every_s = 0.02;
  std::string last;
  int frames = 0, written = 0;
  options.on_frame = [&](const State&, double) {
    ++frames;
    std::ifstream in(options.out / "checkpoint.bin", std::ios::binary);
    const std::string now((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    written += !last.empty() && now != last;
    last = now;
  };
  std::filesystem::remove_all(options.out);
  SeismicRun(sc, options).run();
  EXPECT_EQ(frames, 10);
  // Settling's last checkpoint at 0.04 s (it rests at 0.05 s), then after the 1st, 3rd,
  // 5th, 7th and 9th frames of shaking, each seen at the next frame's callback.
  EXPECT_EQ(written, 5);
}

// README ("the bridge has collapsed when a ring stone fell or more than 5 % of the blocks
// did"): of a model of 100 blocks, one ring stone is a collapse, five other stones are not,
// six are.
TEST(RunMeasures, ABridgeCollapsesWhenARingStoneOrMoreThanOneBlockInTwentyFalls) {
  Model m;
  m.block_count = 100;
  auto collapse = [&](int fallen, int fallen_ring) {
    RunCounts c;
    c.fallen = fallen;
    c.fallen_ring = fallen_ring;
    SeismicRunResult r;
    take_counts(m, c, r);
    return r.collapse;
  };
  EXPECT_TRUE(collapse(1, 1));
  EXPECT_FALSE(collapse(5, 0));
  EXPECT_TRUE(collapse(6, 0));
  EXPECT_FALSE(collapse(0, 0));
}

// A stone has fallen when it dropped more than its size (is_fallen); the ring's fallen
// stones are those of the ring alone: a wall stone that drops 2 m is one fallen stone and
// no ring stone, and the ring stone beside it, dropped too, makes one of each.
TEST(RunMeasures, FallenRingStonesAreTheRingsAlone) {
  const Polyhedron ring_stone = make_box(Vec3(0, 0, 5), Vec3(1, 1, 1)), wall_stone = make_box(Vec3(3, 0, 5), Vec3(1, 1, 1));
  Model m = test::stones_model({{&ring_stone, Motion::free}, {&wall_stone, Motion::free}});
  m.block_tag[0].part = static_cast<int>(Part::ring);
  m.block_tag[1].part = static_cast<int>(Part::wall);
  State s = make_initial_state(m);
  Joints joints;
  s.position[1].z() -= 2;
  RunCounts c = count_damage(m, s, JointThresholds(), joints);
  EXPECT_EQ(c.fallen, 1);
  EXPECT_EQ(c.fallen_ring, 0);
  s.position[0].z() -= 2;
  c = count_damage(m, s, JointThresholds(), joints);
  EXPECT_EQ(c.fallen, 2);
  EXPECT_EQ(c.fallen_ring, 1);
}

// A bridge's run monitors its crown unit (the highest ring stone) unless the scenario names
// blocks: its history has the crown's columns and its summary names it.
TEST(RunMeasures, ABridgesRunMonitorsItsCrownUnit) {
  Scenario sc = read_scenario(kRoot / "scenarios/nishida_a_kobe_dry.toml");
  sc.settings.settle_max_s = 0.002;
  sc.settings.duration_s = 0.002;
  sc.settings.threads = 1;
  const auto out = test::tmp_dir() / "ishibashi_crown_monitor";
  run_into(out, sc);
  const int crown = crown_unit(load_model(sc.model, sc.model_file, model_options(sc.settings)));
  ASSERT_GE(crown, 0);
  std::ifstream summary(out / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(summary)["monitored_block"].get<int>(), crown);
  EXPECT_TRUE(history(out).count("block" + std::to_string(crown) + "_dz_m"));
}

}  // namespace
}  // namespace ishibashi
