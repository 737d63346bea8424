// `ishibashi sweep` end to end on model A with short records: the rows, the IDA and
// fragility outputs; the same rows under `mpirun -np 2` as on one machine; a sweep killed
// half-way resumes without redoing its finished runs, and redoes them all once their
// scenario changed; two variants (dry and with mortar)
// compared on the same records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

#include "command_line.h"
#include "geometry/input_error.h"
#include "analysis/batch/sweep_table.h"
#include "io/sweep_file.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, kMpirunTwoRanks, kRoot, tmp_dir

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

// Model A (with mortar of `mortar_pa`), 0.1 s of shaking; the scenario file's name.
std::filesystem::path scenario_file(const std::string& name, double mortar_pa) {
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  const auto scenario = tmp_dir() / (name + ".toml");
  std::ofstream(scenario) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\nmortar_pa = " << mortar_pa
                          << "\n[run]\nsettle_max_s = 0.1\nduration_s = 0.1\noutput_interval_s = 0.05\n"
                          << "[ground_motion]\nx = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n";
  return scenario;
}

// Two records (the Kobe record's horizontal components swapped), scale factors 0.5 and 1:
// four runs of each scenario.
std::filesystem::path sweep_file(const std::string& scenarios = "scenario = \"" +
                                                                scenario_file("ishibashi_sweep_dry", 0).string() + "\"") {
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  const auto file = tmp_dir() / "ishibashi_sweep.toml";
  const std::string ew = (kobe / "RSN1106_KOBE_KJM090.AT2").string(), ns = (kobe / "RSN1106_KOBE_KJM000.AT2").string(),
                    up = (kobe / "RSN1106_KOBE_KJM-UP.AT2").string();
  std::ofstream(file) << "[sweep]\n" << scenarios << "\nscale = [0.5, 1.0]\n"
                      << "[failure]\ncollapse = true\ncrown_drop_m = 1e-5\n"
                      << "[[record]]\nname = \"kobe_ew_ns\"\nstart_s = 7.6\nx = { file = \"" << ew << "\" }\ny = { file = \""
                      << ns << "\" }\nz = { file = \"" << up << "\" }\n"
                      << "[[record]]\nname = \"kobe_ns_ew\"\nstart_s = 7.6\nx = { file = \"" << ns << "\" }\ny = { file = \""
                      << ew << "\" }\nz = { file = \"" << up << "\" }\n";
  return file;
}

const std::string kSweep = test::program() + " sweep ";

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
  EXPECT_TRUE(std::filesystem::exists(local / "runs/ishibashi_sweep_dry/kobe_ns_ew_0.5/blocks.pvd"));
  EXPECT_FALSE(std::filesystem::exists(local / "comparison.csv"));

  const std::string two = run_command(kMpirunTwoRanks + kSweep + file.string() + " --threads-per-job 1 --out " + mpi.string(), &status);
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

  // Outputs of other inputs are not current: an edited scenario runs every case again.
  std::ofstream(tmp_dir() / "ishibashi_sweep_dry.toml", std::ios::app) << "# edited\n";
  const std::string again = run_command(sweep, &status);
  ASSERT_EQ(status, 0) << again;
  EXPECT_NE(again.find("0 done before"), std::string::npos) << again;
  EXPECT_EQ(count_of(again, ": done (rank 0)"), 4) << again;
  EXPECT_EQ(rows(out).size(), 4u);
}

// A sweep killed while a run is under way goes on from that run's checkpoint (a cluster job's
// wall time may end in the middle of an hours-long run), and its row is the unbroken sweep's.
TEST(Sweep, KilledSweepsRunGoesOnFromItsCheckpoint) {
  std::string text = text_of(sweep_file());
  text.replace(text.find("scale = [0.5, 1.0]"), 18, "scale = [1.0]\nduration_s = 0.5");
  text.erase(text.find("[[record]]\nname = \"kobe_ns_ew\""));  // one case
  const auto file = tmp_dir() / "ishibashi_sweep_one.toml";
  std::ofstream(file) << text;
  const auto whole = tmp_dir() / "ishibashi_sweep_unbroken", killed = tmp_dir() / "ishibashi_sweep_killed_run";
  std::filesystem::remove_all(whole);
  std::filesystem::remove_all(killed);
  int status = 0;
  const std::string unbroken = run_command(kSweep + file.string() + " --threads-per-job 1 --out " + whole.string(), &status);
  ASSERT_EQ(status, 0) << unbroken;
  // SIGKILL as soon as the run has written a checkpoint.
  const std::string sweep = kSweep + file.string() + " --threads-per-job 1 --checkpoint-wall 0.1 --out " + killed.string();
  const std::string checkpoint = (killed / "runs/ishibashi_sweep_dry/kobe_ew_ns_1/checkpoint.bin").string();
  run_command("bash -c '" + sweep + " & pid=$!; until [ -f " + checkpoint + " ] || ! kill -0 $pid 2>/dev/null; do sleep 0.02; done; " +
                  "kill -KILL $pid'",
              &status);
  ASSERT_TRUE(rows(killed).empty()) << "the run finished before it was killed";
  const std::string resumed = run_command(sweep, &status);
  ASSERT_EQ(status, 0) << resumed;
  EXPECT_NE(resumed.find("kobe_ew_ns,1,0: goes on from its checkpoint"), std::string::npos) << resumed;
  ASSERT_EQ(rows(killed).size(), 1u);
  EXPECT_EQ(rows(killed), rows(whole));  // the state hash among them
  EXPECT_FALSE(std::filesystem::exists(checkpoint));  // a finished run's checkpoint goes
}

// Dry and with mortar on the same records and levels: eight runs, a fragility fit per
// variant, and comparison.csv whose case counts add up to the four (record, level) pairs
// and agree with the variants' rows of sweep.csv. A table of other columns is refused.
TEST(Sweep, VariantsAreRunOnTheSameCasesAndCompared) {
  const auto dry = scenario_file("ishibashi_sweep_dry", 0), mortar = scenario_file("ishibashi_sweep_mortar", 2e5);
  const auto file = sweep_file("scenarios = [\"" + dry.string() + "\", \"" + mortar.string() + "\"]");
  const auto out = tmp_dir() / "ishibashi_sweep_variants";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string text = run_command(kSweep + file.string() + " --jobs 2 --threads-per-job 1 --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("8 runs (2 scenarios x 2 records x 2 levels)"), std::string::npos) << text;
  EXPECT_NE(text.find("fragility of ishibashi_sweep_mortar"), std::string::npos) << text;
  EXPECT_NE(text.find("against ishibashi_sweep_dry on the same 4 cases (record, level, member)"), std::string::npos) << text;
  ASSERT_EQ(rows(out).size(), 8u);
  EXPECT_TRUE(std::filesystem::exists(out / "runs/ishibashi_sweep_mortar/kobe_ew_ns_1/blocks.pvd"));
  for (const char* output : {"comparison.csv", "fragility.png", "ida.png"})
    EXPECT_TRUE(std::filesystem::exists(out / output)) << output;

  // The failed column (7th) of each variant, case by case, against the comparison's counts.
  std::map<std::string, std::map<std::string, int>> failed;  // variant -> "record,level" -> failed
  for (const std::string& row : rows(out)) {
    std::vector<std::string> f;
    std::stringstream cells(row);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    failed[f[0]][f[1] + "," + f[2]] = std::stoi(f[6]);
  }
  int both_stand = 0, both_fail = 0, only_dry = 0, only_mortar = 0;
  for (const auto& [key, d] : failed["ishibashi_sweep_dry"]) {
    const int m = failed["ishibashi_sweep_mortar"].at(key);
    both_stand += !d && !m, both_fail += d && m, only_dry += d && !m, only_mortar += !d && m;
  }
  const std::string comparison = text_of(out / "comparison.csv");
  const std::string expected = "ishibashi_sweep_mortar,ishibashi_sweep_dry,4," + std::to_string(both_stand) + "," +
                               std::to_string(both_fail) + "," + std::to_string(only_dry) + "," + std::to_string(only_mortar) + ",";
  EXPECT_NE(comparison.find(expected), std::string::npos) << comparison << "expected " << expected;

  // The single-scenario sweep's table in this folder is refused, with what to do.
  std::ofstream(out / "sweep.csv") << "record,level,scale_factor\nkobe_ew_ns,1,1\n";
  const std::string refused = run_command(kSweep + file.string() + " --out " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(refused.find("its columns are not this version's"), std::string::npos) << refused;
}

// Members (the scenario's [ensemble] draws) as more samples per level: each (record, level)
// run twice with different stones' poses, every run a row and an outcome of the fit.
TEST(Sweep, MembersAreMoreSamplesPerLevel) {
  const auto file = sweep_file("scenario = \"" + scenario_file("ishibashi_sweep_dry", 0).string() + "\"\nmembers = 2");
  const auto out = tmp_dir() / "ishibashi_sweep_members";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string text = run_command(kSweep + file.string() + " --jobs 2 --threads-per-job 1 --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("8 runs (1 scenarios x 2 records x 2 levels x 2 members)"), std::string::npos) << text;
  ASSERT_EQ(rows(out).size(), 8u);
  std::map<std::string, std::set<std::string>> hashes;  // "record,level" -> the members' state hashes
  for (const std::string& row : rows(out)) {
    std::vector<std::string> f;
    std::stringstream cells(row);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    hashes[f[1] + "," + f[2]].insert(f[sweep_column("state_hash")]);
  }
  ASSERT_EQ(hashes.size(), 4u);
  for (const auto& [key, members] : hashes) EXPECT_EQ(members.size(), 2u) << key << ": the members ran the same";
  EXPECT_TRUE(std::filesystem::exists(out / "runs/ishibashi_sweep_dry/kobe_ns_ew_0.5_member_1/summary.json"));
  EXPECT_NE(text_of(out / "fragility_fit.csv").find(",8,"), std::string::npos) << text_of(out / "fragility_fit.csv");
}

// [failure] stop_at_failure: each failed run ends at its first frame that failed, the same
// run as without it up to there (its history a prefix of the whole run's, row for row), and
// every case keeps its verdict; a run that stands goes on to the record's end, unchanged.
TEST(Sweep, StopAtFailureEndsFailedRunsWhereTheyFailed) {
  std::string text = text_of(sweep_file());
  text.replace(text.find("scale = [0.5, 1.0]"), 18, "scale = [0.05, 1.0]\nduration_s = 0.3");
  const auto whole = tmp_dir() / "ishibashi_sweep_whole.toml", stop = tmp_dir() / "ishibashi_sweep_stop.toml";
  std::ofstream(whole) << text;
  text.replace(text.find("crown_drop_m = 1e-5"), 19, "crown_drop_m = 1e-5\nstop_at_failure = true");
  std::ofstream(stop) << text;
  std::map<std::string, std::vector<std::string>> row;  // folder -> its row of sweep.csv
  for (const auto& file : {whole, stop}) {
    const auto out = tmp_dir() / file.stem();
    std::filesystem::remove_all(out);
    int status = 0;
    const std::string log = run_command(kSweep + file.string() + " --jobs 2 --threads-per-job 1 --out " + out.string(), &status);
    ASSERT_EQ(status, 0) << log;
    for (const std::string& line : rows(out)) {
      std::vector<std::string> f;
      std::stringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
      row[(out / "runs/ishibashi_sweep_dry" / (f[1] + "_" + f[2])).string()] = f;
    }
  }
  const std::size_t failed = sweep_column("failed"), shaken = sweep_column("shaking_time_s");
  int stopped = 0, stood = 0;
  for (const std::string case_name : {"kobe_ew_ns_0.05", "kobe_ew_ns_1", "kobe_ns_ew_0.05", "kobe_ns_ew_1"}) {
    const auto a = tmp_dir() / "ishibashi_sweep_whole/runs/ishibashi_sweep_dry" / case_name,
               b = tmp_dir() / "ishibashi_sweep_stop/runs/ishibashi_sweep_dry" / case_name;
    const auto& full = row.at(a.string());
    const auto& cut = row.at(b.string());
    EXPECT_EQ(cut[failed], full[failed]) << case_name << ": the verdict moved";
    EXPECT_NEAR(std::stod(full[shaken]), 0.3, 1e-3) << case_name;  // within a step
    const std::string history = text_of(b / "history.csv"), summary = text_of(b / "summary.json");
    EXPECT_EQ(text_of(a / "history.csv").substr(0, history.size()), history) << case_name;
    if (cut[failed] == "1") {
      ++stopped;
      EXPECT_LT(std::stod(cut[shaken]), 0.3 - 0.01) << case_name;  // a frame (0.05 s) or more short
      EXPECT_NE(summary.find("\"stopped_early\": true"), std::string::npos) << summary;
      EXPECT_NE(summary.find("\"finished\": true"), std::string::npos) << summary;
    } else {
      ++stood;
      EXPECT_EQ(cut, full) << case_name;
      EXPECT_NE(summary.find("\"stopped_early\": false"), std::string::npos) << summary;
    }
  }
  EXPECT_GE(stopped, 1) << "no run failed: the test shows nothing";
  EXPECT_GE(stood, 1) << "every run failed: the test shows nothing";
}

// A case whose run fails (here the scenario monitors a block the model lacks, which only
// the built model can tell) says why once, the sweep goes on with the others and exits
// with an error, and sweep.csv gets no row for it.
TEST(Sweep, FailedCaseSaysWhyOnceAndGetsNoRow) {
  const auto scenario = scenario_file("ishibashi_sweep_bad_monitor", 0);
  std::ofstream(scenario, std::ios::app) << "[monitor]\nblocks = [100000]\n";
  const auto out = tmp_dir() / "ishibashi_sweep_failed";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string said = run_command(kSweep + sweep_file("scenario = \"" + scenario.string() + "\"").string() +
                                           " --jobs 2 --threads-per-job 1 --out " + out.string(),
                                       &status);
  EXPECT_NE(status, 0) << said;
  EXPECT_EQ(count_of(said, "[monitor] block 100000 does not exist"), 4) << said;
  EXPECT_NE(said.find("0 runs done now, 0 done before, 4 failed"), std::string::npos) << said;
  EXPECT_TRUE(rows(out).empty());
}

// A sweep file with both `scenario` and `scenarios`, two variants of one name, a name with
// a comma or two levels of one label (names are run folders and fields of the rows) is
// refused with what is wrong, and so are the inputs that would make a whole sweep run for nothing.
TEST(Sweep, AmbiguousScenariosAreRefused) {
  const auto dry = scenario_file("ishibashi_sweep_dry", 0);
  auto message = [](const std::filesystem::path& file) {
    try {
      read_sweep(file);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string both = message(sweep_file("scenario = \"" + dry.string() + "\"\nscenarios = [\"" + dry.string() + "\"]"));
  EXPECT_NE(both.find("needs either scenario"), std::string::npos) << both;
  const auto twin = tmp_dir() / "twin";
  std::filesystem::create_directories(twin);
  std::filesystem::copy_file(dry, twin / dry.filename(), std::filesystem::copy_options::overwrite_existing);
  const std::string same = message(sweep_file("scenarios = [\"" + dry.string() + "\", \"" + (twin / dry.filename()).string() + "\"]"));
  EXPECT_NE(same.find("'scenarios' names 'ishibashi_sweep_dry' twice"), std::string::npos) << same;
  const auto comma = twin / "dry,mortar.toml";  // would split its rows of sweep.csv
  std::filesystem::copy_file(dry, comma, std::filesystem::copy_options::overwrite_existing);
  const std::string named = message(sweep_file("scenarios = [\"" + comma.string() + "\"]"));
  EXPECT_NE(named.find("must be letters, digits"), std::string::npos) << named;
  // A scenario that ends its runs at their collapse: with crown-drop criteria such a run
  // could stop before it failed; the sweep's own stop is named instead.
  const auto stops = twin / "stops.toml";
  std::ofstream(stops) << text_of(dry).replace(text_of(dry).find("[run]\n"), 6, "[run]\nstop_at = \"collapse\"\n");
  const std::string stopped = message(sweep_file("scenario = \"" + stops.string() + "\""));
  EXPECT_NE(stopped.find("stops.toml ends its runs at their collapse ([run] stop_at = \"collapse\"); a sweep ends them at "
                         "its own failure criteria: [failure] stop_at_failure = true"),
            std::string::npos)
      << stopped;
  // Two levels of one label ("%g": 0.5 and 0.5000001) would name the same runs' folders.
  const auto file = sweep_file();
  std::string text = text_of(file);
  text.replace(text.find("scale = [0.5, 1.0]"), 18, "scale = [0.5, 0.5000001]");
  std::ofstream(file) << text;
  const std::string level = message(file);
  EXPECT_NE(level.find("lists the level 0.5 twice"), std::string::npos) << level;
  // A negative duration or failure threshold (their unset defaults are -1) is refused, not
  // read as "the scenario's" or "not a criterion"; so are a [failure] that names no failure
  // and a record whose start lies past its end, before any run (each would otherwise run
  // the whole sweep for nothing).
  for (const auto& [from, to, key] :
       {std::tuple{"crown_drop_m = 1e-5", "crown_drop_m = -0.02", "'crown_drop_m' is -0.02"},
        std::tuple{"crown_drop_m = 1e-5", "fallen_stones = -1", "'fallen_stones' is -1"},
        std::tuple{"scale = [0.5, 1.0]", "scale = [0.5, 1.0]\nduration_s = -1", "'duration_s' is -1"},
        std::tuple{"collapse = true\ncrown_drop_m = 1e-5", "collapse = false", "[failure] names no failure"},
        std::tuple{"start_s = 7.6", "start_s = 600",
                   "lies outside the record; it must lie in [0, 149.98) s, the length of its shortest component, "}}) {
    const auto bad = sweep_file();
    std::string sweep_text = text_of(bad);
    sweep_text.replace(sweep_text.find(from), std::string(from).size(), std::string(to));
    std::ofstream(bad) << sweep_text;
    const std::string refused = message(bad);
    EXPECT_NE(refused.find(key), std::string::npos) << refused;
    if (std::string(to) == "start_s = 600")  // where: the sweep file's line and record, the record's file
      EXPECT_NE(refused.find(":7: record 'kobe_ew_ns': ground motion: start_s = 600 s ("), std::string::npos) << refused;
  }
}

}  // namespace
}  // namespace ishibashi
