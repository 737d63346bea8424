// `ishibashi study --quick` end to end: the tables, a report with every figure, and a
// second call that keeps the current outputs; the jobs across MPI ranks; a bad study file
// names its line.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "analysis/batch/job_queue.h"
#include "command_line.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, kRoot, tmp_dir

// A report that cannot be drawn says why: its script missing (a program copied away from
// its checkout once read as "needs python3 with matplotlib"), or the status it ended with.
TEST(ReportScript, SaysWhyItDrewNothing) {
  const auto empty = tmp_dir() / "ishibashi_report_nothing";
  std::filesystem::create_directories(empty);
  const std::string missing = run_report_script("no_such_script.py", empty);
  EXPECT_NE(missing.find(ISHIBASHI_SOURCE_DIR "/analysis/report/no_such_script.py is missing: the program runs the report "
                         "scripts installed beside it"),
            std::string::npos)
      << missing;
  const std::string failed = run_report_script("mode_shapes.py", empty);  // no modes.csv to draw
  EXPECT_NE(failed.find("mode_shapes.py ended with status "), std::string::npos) << failed;
  EXPECT_EQ(failed.find("status 0"), std::string::npos) << failed;
}

TEST(Study, QuickStudyWritesTablesAndAReportWithEveryFigureThenKeepsCurrentOutputs) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_study_quick";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string study = test::program() + " study --quick --jobs 2 --out " + out.string();
  const std::string first = run_command(study, &status);
  ASSERT_EQ(status, 0) << first;
  EXPECT_EQ(count_of(first, ": done"), 4) << first;  // two runs, model A's frequencies under both joint rules
  // The tables: a row per job.
  EXPECT_EQ(count_of(text_of(out / "runs.csv"), "\n"), 3);
  EXPECT_EQ(count_of(text_of(out / "frequencies.csv"), "\n"), 3);
  // Model A's first modes by modal analysis: 22.53, 20.99, 41.91 Hz.
  EXPECT_NE(text_of(out / "frequencies.csv").find(",22.52"), std::string::npos) << text_of(out / "frequencies.csv");
  // The report: ground motion, crown, the mortar run's bond utilisation, spectra, energy,
  // the mode shapes of each frequency analysis and one snapshot per run, and an animation of each run
  // (scripts/check_report.py checks their frames in CI).
  const std::string html = text_of(out / "report.html");
  EXPECT_EQ(count_of(html, "src='data:image/png;base64,"), 9) << html.substr(0, 500);
  EXPECT_EQ(count_of(html, "src='data:image/gif;base64,"), 2);
  const std::string md = text_of(out / "report.md");
  EXPECT_EQ(count_of(md, "](figures/"), 11);
  // What it said while it worked: a progress line after each job, the last with all done.
  EXPECT_EQ(count_of(first, "progress: "), 4) << first;
  EXPECT_NE(first.find("progress: 4 of 4 jobs done\n"), std::string::npos) << first;
  for (const char* run : {"nishida_a_kobe_dry", "nishida_a_kobe_mortar"}) {
    EXPECT_TRUE(std::filesystem::exists(out / "runs" / run / "view.pvsm")) << run;
    EXPECT_EQ(text_of(out / "runs" / run / "report.png").substr(0, 4), "\x89PNG") << run;  // as `run` draws it
  }
  // The study's own figures and verdicts beside ours (the study file's [reference]).
  EXPECT_NE(md.find("## Natural frequencies against the study"), std::string::npos);
  EXPECT_NE(md.find("| 17.6 |"), std::string::npos) << "model A's x frequency in the study";
  EXPECT_NE(md.find("| collapses in plane: first horizontal crack at 4.0 s"), std::string::npos);
  // How it fails: neither loses a stone or hinges its ring in 0.3 s.
  EXPECT_EQ(count_of(md, "| no stone fell; no ring joint hinged |"), 2) << md;
  EXPECT_EQ(count_of(text_of(out / "reference.csv"), "\n"), 14);  // header, 3 models, 5 verdicts, 5 outcomes
  for (const char* figure : {"ground_motion.png", "crown_displacement.png", "bond_utilisation.png", "impulse_spectra.png", "energy.png",
                             "mode_shapes_nishida_a_corners.png", "mode_shapes_nishida_a_moments.png"})
    EXPECT_GT(std::filesystem::file_size(out / "figures" / figure), 10000u) << figure;

  const std::string second = run_command(study, &status);
  ASSERT_EQ(status, 0) << second;
  EXPECT_EQ(count_of(second, "current, kept"), 4) << second;
  EXPECT_NE(second.find("0 jobs ran, 4 were current"), std::string::npos) << second;
}

TEST(Study, InterruptedStudyGoesOnFromItsRunsCheckpointAndEndsAsIfNeverStopped) {
  const auto whole = tmp_dir() / "ishibashi_study_whole", stopped = tmp_dir() / "ishibashi_study_stopped";
  std::filesystem::remove_all(whole);
  std::filesystem::remove_all(stopped);
  const std::string study = test::program() + " study --quick --jobs 1 --threads-per-job 1 --no-report --out ";
  int status = 0;
  const std::string reference = run_command(study + whole.string(), &status);
  ASSERT_EQ(status, 0) << reference;
  // SIGINT half a second after the first run's first frame (its 0.45 s take about 4 s here).
  const auto run = stopped / "runs" / "nishida_a_kobe_dry";
  const std::string stop = "bash -c '" + study + stopped.string() + " & s=$!; while [ ! -f " + (run / "blocks.pvd").string() +
                           " ] && kill -0 $s 2> /dev/null; do sleep 0.05; done; sleep 0.5; kill -INT $s; wait $s'";
  const std::string first = run_command(stop, &status);
  EXPECT_NE(status, 0) << first;
  ASSERT_TRUE(std::filesystem::exists(run / "checkpoint.bin")) << first;
  const std::string second = run_command(study + stopped.string(), &status);
  ASSERT_EQ(status, 0) << second;
  EXPECT_NE(second.find("run nishida_a_kobe_dry: goes on from its checkpoint"), std::string::npos) << second;
  EXPECT_FALSE(std::filesystem::exists(run / "checkpoint.bin"));  // done with
  // Bit-identical to the run never stopped: its whole history and final state.
  const auto reference_run = whole / "runs" / "nishida_a_kobe_dry";
  EXPECT_EQ(text_of(run / "history.csv"), text_of(reference_run / "history.csv"));
  auto hash = [](const std::filesystem::path& summary) {
    const std::string text = text_of(summary);
    const std::size_t at = text.find("\"state_hash\"");
    return at == std::string::npos ? std::string() : text.substr(at, 40);
  };
  EXPECT_FALSE(hash(run / "summary.json").empty());
  EXPECT_EQ(hash(run / "summary.json"), hash(reference_run / "summary.json"));
}

TEST(Study, RunsAsEnsemblesGiveTheirProbabilitiesAndTheStudysOutcomeInTheReport) {
  const auto file = tmp_dir() / "ishibashi_study_members.toml";
  std::ofstream(file) << "[study]\nname = \"Members\"\nscenarios = [\"" << (kRoot / "scenarios/nishida_a_kobe_dry.toml").string()
                      << "\"]\nsnapshot_times_s = [0.1]\nduration_s = 0.15\nmembers = 3\n"
                      << "[reference.outcome]\nnishida_a_kobe_dry = \"stands\"\n";
  const auto out = tmp_dir() / "ishibashi_study_members";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string study = test::program() + " study " + file.string() + " --members 2 --out " + out.string();
  const std::string first = run_command(study, &status);
  ASSERT_EQ(status, 0) << first;
  EXPECT_NE(first.find("an ensemble of 2 members"), std::string::npos) << first;  // --members replaces the file's 3
  const auto run = out / "runs" / "nishida_a_kobe_dry";
  EXPECT_TRUE(std::filesystem::exists(run / "member_001" / "summary.json"));
  EXPECT_FALSE(std::filesystem::exists(run / "member_002"));
  for (const char* member : {"member_000", "member_001"})  // each member's own picture, as `run --members` draws
    EXPECT_EQ(text_of(run / member / "report.png").substr(0, 4), "\x89PNG") << member;
  const std::string runs = text_of(out / "runs.csv");
  EXPECT_NE(runs.find(",2,member_00"), std::string::npos) << runs;  // members, the most common outcome's member
  EXPECT_NE(runs.find("p_collapse,p_collapse_lo"), std::string::npos) << runs;
  // Neither member collapses in 0.15 s: p(collapse) 0 of 2, [0, 3.84 / 5.84]; the study's
  // outcome (here: stands) has p 1 [0.34, 1].
  const std::string md = text_of(out / "report.md");
  EXPECT_NE(md.find("| 0.00 [0.00-0.66] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| stands: 1.00 [0.34-1.00] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 0-0 |"), std::string::npos) << md;  // stones fallen, least and most
  EXPECT_NE(md.find("| no stone fell; no ring joint hinged (members: no stone fell 2) |"), std::string::npos) << md;  // how it fails
  EXPECT_NE(md.find("](figures/snapshot_nishida_a_kobe_dry_member_00"), std::string::npos) << md;  // the worst outcome
  const std::string second = run_command(study, &status);
  EXPECT_EQ(status, 0) << second;
  EXPECT_NE(second.find("0 jobs ran, 1 were current"), std::string::npos) << second;
}

// `study --damping implicit --dt 4e-5` runs every run so (the fast path's study), and the
// same study without them is not current: the run settings are part of a run's key.
TEST(Study, RunSettingsOnTheCommandLineReachEveryRunAndItsKey) {
  const auto file = tmp_dir() / "ishibashi_study_settings.toml";
  std::ofstream(file) << "[study]\nname = \"Settings\"\nscenarios = [\"" << (kRoot / "scenarios/nishida_a_kobe_dry.toml").string()
                      << "\"]\nsnapshot_times_s = [0.05]\nduration_s = 0.05\n";
  const auto out = tmp_dir() / "ishibashi_study_settings";
  std::filesystem::remove_all(out);
  const std::string study = test::program() + " study " + file.string() + " --no-report --out " + out.string();
  int status = 0;
  const std::string fast = run_command(study + " --damping implicit --dt 4e-5", &status);
  ASSERT_EQ(status, 0) << fast;
  const std::string summary = text_of(out / "runs" / "nishida_a_kobe_dry" / "summary.json");
  EXPECT_NE(summary.find("\"damping\": \"implicit\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"dt_s\": 4e-05"), std::string::npos) << summary;
  const std::string again = run_command(study + " --damping implicit --dt 4e-5", &status);
  EXPECT_NE(again.find("0 jobs ran, 1 were current"), std::string::npos) << again;
  const std::string reference = run_command(study, &status);
  ASSERT_EQ(status, 0) << reference;
  EXPECT_NE(reference.find("1 jobs ran, 0 were current"), std::string::npos) << reference;
  EXPECT_NE(text_of(out / "runs" / "nishida_a_kobe_dry" / "summary.json").find("\"damping\": \"study\""), std::string::npos);
}

// `study --stop-at collapse` reaches its runs: the tied stack of three, which topples whole
// within its 3 s, ends at its collapse, and the report says that such a run's counts are
// those at the collapse.
TEST(Study, StopAtCollapseEndsCollapsingRunsAndTheReportSaysSo) {
  const auto file = tmp_dir() / "ishibashi_study_stop.toml";
  std::ofstream(file) << "[study]\nname = \"Stop\"\nscenarios = [\""
                      << (kRoot / "scenarios/examples/stack_of_three_tied_kobe.toml").string()
                      << "\"]\nsnapshot_times_s = [1.0]\nduration_s = 3.0\n";
  const auto out = tmp_dir() / "ishibashi_study_stop";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string log = run_command(
      test::program() + " study " + file.string() + " --stop-at collapse --threads-per-job 1 --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const auto summary = nlohmann::json::parse(text_of(out / "runs" / "stack_of_three_tied_kobe" / "summary.json"));
  EXPECT_EQ(summary["settings"]["stop_at"], "collapse");
  EXPECT_TRUE(summary["collapse"].get<bool>());
  EXPECT_TRUE(summary["stopped_early"].get<bool>());
  EXPECT_LT(summary["shaking_time_s"].get<double>(), 2.9);
  EXPECT_NE(text_of(out / "report.md").find("Runs that collapsed ended there (--stop-at collapse)"), std::string::npos);
  // How it fails, beside what the study says: the run's own sentence (summary.json).
  const std::string how = summary["how_it_fails"]["text"].get<std::string>();
  EXPECT_EQ(how.rfind("imported stones from ", 0), 0u) << how;
  EXPECT_NE(text_of(out / "report.md").find("| " + how + " |"), std::string::npos) << how;
}

// Under `mpirun -np 2` rank 0 hands the runs' members out as jobs of their own, then the
// runs' jobs, and writes the tables: each member ends in the same state as on one machine,
// and jobs.csv says each run ran.
TEST(Study, MpirunRanksRunTheMembersAndJobsAsOneMachineDoes) {
  const auto file = tmp_dir() / "ishibashi_study_mpi.toml";
  std::ofstream(file) << "[study]\nname = \"Ranks\"\nscenarios = [\"" << (kRoot / "scenarios/nishida_a_kobe_dry.toml").string()
                      << "\", \"" << (kRoot / "scenarios/nishida_a_kobe_mortar.toml").string()
                      << "\"]\nsnapshot_times_s = [0.05]\nduration_s = 0.05\nmembers = 2\n";
  const auto local = tmp_dir() / "ishibashi_study_mpi_local", ranks = tmp_dir() / "ishibashi_study_mpi_ranks";
  std::filesystem::remove_all(local);
  std::filesystem::remove_all(ranks);
  const std::string study = test::program() + " study " + file.string() +
                            " --threads-per-job 1 --no-report --damping implicit --dt 4e-5 --out ";
  int status = 0;
  const std::string one = run_command(study + local.string() + " --jobs 2", &status);
  ASSERT_EQ(status, 0) << one;
  const std::string two = run_command(kMpirunTwoRanks + study + ranks.string(), &status);
  ASSERT_EQ(status, 0) << two;
  EXPECT_NE(two.find("2 jobs, 2 MPI ranks"), std::string::npos) << two;
  EXPECT_EQ(count_of(two, ": ran\n"), 4) << "each member once: " << two;
  EXPECT_GE(count_of(two, "(rank 1): ran"), 1) << "rank 1 ran no member: " << two;
  EXPECT_NE(two.find("study: 2 jobs ran, 0 were current, 0 failed"), std::string::npos) << two;
  EXPECT_EQ(count_of(text_of(ranks / "jobs.csv"), ",ran,"), 2) << text_of(ranks / "jobs.csv");
  EXPECT_EQ(count_of(text_of(ranks / "runs.csv"), "\n"), 3) << text_of(ranks / "runs.csv");
  for (const char* run : {"nishida_a_kobe_dry", "nishida_a_kobe_mortar"})
    for (const char* member : {"member_000", "member_001"}) {
      ASSERT_FALSE(state_hash_of(local / "runs" / run / member).empty()) << run << " " << member;
      EXPECT_EQ(state_hash_of(ranks / "runs" / run / member), state_hash_of(local / "runs" / run / member))
          << run << " " << member;
    }
}

TEST(Study, BadStudyFileNamesTheFileAndLine) {
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_bad_study.toml";
  // Writes the study file, runs `study` on it and returns what it printed; it must fail.
  auto refused = [&](const std::string& text) {
    std::ofstream(file) << text;
    int status = 0;
    const std::string output = run_command(test::program() + " study " + file.string(), &status);
    EXPECT_NE(status, 0) << text;
    return output;
  };
  const std::string output = refused("[study]\nname = \"x\"\nscenarios = [\"nowhere.toml\"]\n[frequencies]\nmodes = 3\nimpulse = 2\n");
  EXPECT_NE(output.find(file.string() + ":6: unknown key 'impulse' in [frequencies]"), std::string::npos) << output;
  const std::string missing = refused("[study]\nscenarios = [\"nowhere.toml\"]\n");
  EXPECT_NE(missing.find("nowhere.toml does not exist"), std::string::npos) << missing;
  const std::string unknown =
      refused("[study]\nscenarios = [\"nowhere.toml\"]\n[reference.says]\nnowhere = \"stands\"\nelsewhere = \"falls\"\n");
  EXPECT_NE(unknown.find(file.string() + ":5: 'elsewhere' is no scenario file of [study] scenarios"), std::string::npos)
      << unknown;
  const std::string short_list = refused("[study]\nmodels = [\"a.toml\"]\n[reference]\nfrequencies_hz = { a = [1.0, 2.0] }\n");
  EXPECT_NE(short_list.find(file.string() + ":4: 'a' must be [x, y, z] in Hz"), std::string::npos) << short_list;
  const std::string rule = refused("[study]\nmodels = [\"a.toml\"]\n[frequencies]\njoint_rules = [\"corners\", \"edges\"]\n");
  EXPECT_NE(rule.find(file.string() + ":4: 'joint_rules' may only hold \"corners\", \"moments\""), std::string::npos) << rule;
  const std::string verdict = refused("[study]\nscenarios = [\"nowhere.toml\"]\n[reference.outcome]\nnowhere = \"survives\"\n");
  EXPECT_NE(verdict.find(file.string() + ":4: 'nowhere' must be \"collapse\", \"stands\" or \"no_stone_falls\""),
            std::string::npos)
      << verdict;
  const std::string members = refused("[study]\nscenarios = [\"nowhere.toml\"]\nmembers = -2\n");
  EXPECT_NE(members.find(file.string() + ":3: "), std::string::npos) << members;
  // Two files of one stem would write one folder (at once, with --jobs 2).
  const std::string twice = refused("[study]\nscenarios = [\"a/run.toml\", \"b/run.toml\"]\n");
  EXPECT_NE(twice.find(file.string() + ":2: 'scenarios' names 'run' twice"), std::string::npos) << twice;
  const std::string nan = refused("[study]\nscenarios = [\"nowhere.toml\"]\nduration_s = nan\n");
  EXPECT_NE(nan.find(file.string() + ":3: 'duration_s' is nan; it must be a finite number"), std::string::npos) << nan;
  // The frequencies' numbers out of range are refused at their line (they were checked
  // after reading, without one).
  for (const auto& [text, message] :
       {std::pair<std::string, std::string>{"[study]\nscenarios = [\"nowhere.toml\"]\n[frequencies]\nmodes = 0\n", ":4: 'modes' is 0; it must be at least 1 and at most 500"},
        {"[study]\nscenarios = [\"nowhere.toml\"]\n[quick]\nimpulse_s = -1\n", ":4: 'impulse_s' is -1; it must be >= 0"}}) {
    const std::string out = refused(text);
    EXPECT_NE(out.find(file.string() + message), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace ishibashi
