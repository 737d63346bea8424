// `ishibashi run` end to end on a small model: the outputs load in VTK with the arrays
// named in the docs, the ParaView state file plays them, and a run stopped by a signal
// leaves valid files. (scripts/paraview_check.sh loads the state file in ParaView itself.)
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command_line.h"
#include "engine/cores.h"
#include "geometry/block_files.h"
#include "io/vtk_input.h"

namespace ishibashi {
namespace {

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;

// A short scenario on model A with the Kobe record (absolute paths: written to /tmp).
std::filesystem::path short_scenario(double duration_s, double settle_max_s = 0.1, double output_interval_s = 0.05) {
  const auto f = std::filesystem::temp_directory_path() /
                 ("ishibashi_short_" + std::to_string(settle_max_s) + "_" + std::to_string(output_interval_s) + ".toml");
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  std::ofstream(f) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\n"
                   << "[run]\nsettle_max_s = " << settle_max_s << "\nduration_s = " << duration_s
                   << "\noutput_interval_s = " << output_interval_s << "\n"
                   << "[ground_motion]\nstart_s = 7.0\n"
                   << "x = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n"
                   << "y = { file = \"" << (kobe / "RSN1106_KOBE_KJM000.AT2").string() << "\" }\n"
                   << "z = { file = \"" << (kobe / "RSN1106_KOBE_KJM-UP.AT2").string() << "\" }\n";
  return f;
}

// The values of property `name` of proxy `id` in a state file (one property per line).
std::vector<std::string> state_values(const std::string& pvsm, const std::string& id, const std::string& name) {
  const std::size_t at = pvsm.find("id=\"" + id + "." + name + "\"");
  std::vector<std::string> values;
  if (at == std::string::npos) return values;
  const std::string line = pvsm.substr(at, pvsm.find('\n', at) - at);
  for (std::size_t v = line.find("value=\""); v != std::string::npos; v = line.find("value=\"", v + 1)) {
    const std::size_t begin = v + 7;
    values.push_back(line.substr(begin, line.find('"', begin) - begin));
  }
  return values;
}

// view.pvsm names the series without a folder, plays their frames and colours on one
// scale that holds every standing stone's displacement in every frame.
void expect_valid_state(const std::filesystem::path& out, const std::vector<PvdEntry>& blocks) {
  std::ifstream file(out / "view.pvsm");
  ASSERT_TRUE(file) << "no view.pvsm in " << out;
  std::stringstream text;
  text << file.rdbuf();
  const std::string pvsm = text.str();
  EXPECT_EQ(state_values(pvsm, "100", "FileName"), std::vector<std::string>{"blocks.pvd"});
  EXPECT_EQ(state_values(pvsm, "104", "FileName"), std::vector<std::string>{"contacts.pvd"});
  const auto end = state_values(pvsm, "142", "EndTime"), start = state_values(pvsm, "142", "AnimationTime");
  ASSERT_EQ(end.size(), 1u);
  ASSERT_EQ(start.size(), 1u);
  EXPECT_NEAR(std::stod(end[0]), blocks.back().time_s, 1e-5);
  EXPECT_NEAR(std::stod(start[0]), blocks.front().time_s, 1e-5);
  const auto rgb = state_values(pvsm, "110", "RGBPoints");
  ASSERT_EQ(rgb.size() % 4, 0u);
  ASSERT_GE(rgb.size(), 8u);
  const double top = std::stod(rgb[rgb.size() - 4]);
  double largest = 0;
  for (const auto& e : blocks) {
    vtkUnstructuredGrid* g = read_vtu(e.file);
    vtkDataArray* d = g->GetCellData()->GetArray("displacement_relative_to_ground");
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
      if (g->GetCellData()->GetArray("part")->GetComponent(c, 0) != 0 && g->GetCellData()->GetArray("fallen")->GetComponent(c, 0) == 0)
        largest = std::max(largest, std::hypot(d->GetComponent(c, 0), d->GetComponent(c, 1), d->GetComponent(c, 2)));
    g->Delete();
  }
  EXPECT_GE(top, largest * (1 - 1e-5));
  EXPECT_LE(top, std::max(largest * (1 + 1e-5), 1e-3));  // the scale is the largest, not a guess
}

void expect_valid_outputs(const std::filesystem::path& out) {
  const auto blocks = read_pvd(out / "blocks.pvd");
  ASSERT_GE(blocks.size(), 2u);
  for (const auto& e : blocks) {
    vtkUnstructuredGrid* g = read_vtu(e.file);
    EXPECT_EQ(g->GetNumberOfCells(), 166);
    for (const char* name : {"displacement", "velocity", "part", "fixed", "fallen"}) EXPECT_NE(g->GetCellData()->GetArray(name), nullptr) << name;
    g->Delete();
  }
  const auto contacts = read_pvd(out / "contacts.pvd");
  ASSERT_EQ(contacts.size(), blocks.size());
  // At the start all 1,808 sub-contacts of the ring; later the frames may have fewer (how
  // many depends on how far the run got before it was stopped).
  vtkUnstructuredGrid* first = read_vtu(contacts.front().file);
  EXPECT_GT(first->GetNumberOfPoints(), 1000);
  first->Delete();
  vtkUnstructuredGrid* c = read_vtu(contacts.back().file);
  EXPECT_GT(c->GetNumberOfPoints(), 0);
  for (const char* name : {"normal_stress_pa", "shear_stress_pa", "opening_m", "slip_m", "state"})
    EXPECT_NE(c->GetPointData()->GetArray(name), nullptr) << name;
  c->Delete();
  std::ifstream history(out / "history.csv");
  std::string header, line, last;
  std::getline(history, header);
  EXPECT_NE(header.find("block"), std::string::npos);  // the monitored crown unit
  int rows = 0;
  while (std::getline(history, line)) {
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, static_cast<int>(blocks.size()));
  EXPECT_EQ(std::count(last.begin(), last.end(), ','), std::count(header.begin(), header.end(), ','));  // whole row
  std::ifstream summary(out / "summary.json");
  std::stringstream text;
  text << summary.rdbuf();
  EXPECT_NE(text.str().find("\"largest_crown_drop_m\""), std::string::npos);
  EXPECT_EQ(text.str().back(), '\n');
  EXPECT_TRUE(std::filesystem::exists(out / "scenario.toml"));
  expect_valid_state(out, blocks);
  for (const auto& f : std::filesystem::directory_iterator(out))
    EXPECT_EQ(f.path().string().find(".tmp"), std::string::npos) << f.path();
}

// ... and report.png, the run at a glance (analysis/report/run_report.py), unless --no-report.
TEST(Run, ShortSeismicRunWritesOutputsVtkReads) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run";
  std::filesystem::remove_all(out);
  const std::string cmd = test::program() + " run --quiet " + short_scenario(0.05, 0.05).string() + " --out " + out.string();
  int status = 0;
  const std::string said = test::run_command(cmd, &status);
  ASSERT_EQ(status, 0) << said;
  expect_valid_outputs(out);
  EXPECT_NE(said.find("summary.json, report.png (the run at a glance)"), std::string::npos) << said;
  EXPECT_EQ(said.find("warning"), std::string::npos) << said;
  EXPECT_EQ(test::text_of(out / "report.png").substr(0, 8), "\x89PNG\r\n\x1a\n");
  ASSERT_EQ((test::run_command(cmd + " --no-report", &status), status), 0);
  EXPECT_FALSE(std::filesystem::exists(out / "report.png"));
}

// Frames are for watching: asking for five times as many must not change the run (the
// settling is judged every 0.05 s whatever the frames; model A settles in about 0.15 s).
TEST(Run, FinerFramesDoNotChangeTheRun) {
  std::string summaries[2];
  for (int k = 0; k < 2; ++k) {
    const auto out = std::filesystem::temp_directory_path() / ("ishibashi_frames_" + std::to_string(k));
    std::filesystem::remove_all(out);
    const std::string cmd = test::program() + " run --quiet " + short_scenario(0.05, 1.0, k ? 0.01 : 0.05).string() +
                            " --out " + out.string() + " > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream summary(out / "summary.json");
    std::stringstream text;
    text << summary.rdbuf();
    summaries[k] = text.str();
  }
  auto field = [](const std::string& json, const std::string& name) {
    const std::size_t at = json.find("\"" + name + "\"");
    return at == std::string::npos ? std::string("missing") : json.substr(at, json.find('\n', at) - at);
  };
  for (const char* name : {"settle_time_s", "state_hash", "motion_hash", "steps"})
    EXPECT_EQ(field(summaries[0], name), field(summaries[1], name)) << name;
}

TEST(Run, InterruptedRunLeavesValidFiles) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_interrupted";
  std::filesystem::remove_all(out);
  // SIGINT 1 s after the first frame of a run that would take much longer (after the
  // frame, not after a fixed time, so that a loaded machine cannot stop it before it wrote any).
  const std::string cmd = "bash -c '" + test::program() + " run --quiet " + short_scenario(20.0).string() +
                          " --out " + out.string() + " & run=$!; while [ ! -f " + (out / "blocks.pvd").string() +
                          " ] && kill -0 $run 2> /dev/null; do sleep 0.05; done; sleep 1; kill -INT $run; wait $run'";
  const int status = std::system(cmd.c_str());
  EXPECT_NE(status, 0);  // it was stopped
  expect_valid_outputs(out);
  std::ifstream summary(out / "summary.json");
  std::stringstream text;
  text << summary.rdbuf();
  EXPECT_NE(text.str().find("\"interrupted\": true"), std::string::npos) << text.str();
}

// run --profile prints each stage's split of the team's time; --trace writes the steps
// asked for as a Chrome trace; a step range that is not FROM:TO is refused before the run.
// A disk that fills mid-run (here a file-size limit of 100 KiB, which the ring's third
// frame passes, as a full disk does: the write fails): the run stops at that frame saying
// which file and why, and what it leaves is whole. VTK's own file writer returned success
// on a file cut short, or crashed freeing an array twice.
TEST(Run, FullDiskStopsTheRunAndLeavesWholeFiles) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_full_disk";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string output = test::run_command("bash -c \"trap '' XFSZ; ulimit -f 100; " + test::program() +
                                                   " run --quiet " + short_scenario(0.05, 0.05).string() + " --out " +
                                                   out.string() + "\"",
                                               &status);
  EXPECT_NE(status, 0) << output;
  EXPECT_NE(output.find("cannot write " + (out / "blocks_000002.vtu").string() + ": File too large"), std::string::npos)
      << output;
  EXPECT_FALSE(std::filesystem::exists(out / "blocks_000002.vtu"));
  expect_valid_outputs(out);  // the two frames before it, each whole, and no temporary file
}

// Two runs given one --out would each write frames, history and summary over the other's
// (seen: a 0.3 s run's series beside a 0.1 s run's summary). The second is refused while
// the first runs; killed with SIGKILL, the first leaves no claim behind.
TEST(Run, SecondRunIntoAFolderInUseIsRefused) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_busy_folder";
  std::filesystem::remove_all(out);
  const std::string run = test::program() + " run --quiet --out " + out.string() + " ";
  int status = 0;
  const std::string output = test::run_command(
      "bash -c '" + run + short_scenario(20.0).string() + " > /dev/null 2>&1 & first=$!; while [ ! -f " +
          (out / "blocks.pvd").string() + " ] && kill -0 $first 2> /dev/null; do sleep 0.05; done; " + run +
          short_scenario(0.05, 0.05).string() + "; echo second $?; kill -KILL $first; wait $first; " + run +
          short_scenario(0.05, 0.05).string() + " > /dev/null; echo third $?'",
      &status);
  EXPECT_NE(output.find(out.string() + ": another run is writing into this folder now"), std::string::npos) << output;
  EXPECT_NE(output.find("second 2"), std::string::npos) << output;
  EXPECT_NE(output.find("third 0"), std::string::npos) << output;
  expect_valid_outputs(out);
}

// Frames at every step of the whole Kobe record (146 s of it, 34 million steps of model F:
// at least 28,000 GB) are refused at the first frame, in seconds, not when the disk fills.
TEST(Run, FramesTheDiskCannotHoldAreRefusedAtTheFirstFrame) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_frames_too_many";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  if (std::filesystem::space(out).available > 1e14) GTEST_SKIP() << "a disk with more than 100 TB free";
  int status = 0;
  const std::string output = test::run_command(test::program() + " run --quiet " +
                                                   (kRoot / "scenarios/nishida_f_kobe_dry.toml").string() +
                                                   " --duration 0 --output-interval 1e-9 --threads 1 --out " + out.string(),
                                               &status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << output;
  EXPECT_NE(output.find(": the shaking's 34223173 frames (a frame every 4.27e-06 s) need at least"), std::string::npos)
      << output;
  EXPECT_NE(output.find("raise output_interval_s (--output-interval)"), std::string::npos) << output;
  EXPECT_EQ(read_pvd(out / "blocks.pvd").size(), 1u);  // the first frame, nothing after it
}

// Into a log file (no terminal): a line every 0.25 s of settling (at its first frame past
// each; frames here 0.03 s apart) and every tenth of the shaking, after the run's own
// header, where a progress bar's redraws made one line of hundreds (and settling, minutes
// of a large bridge, said nothing).
TEST(Run, ProgressIntoALogFileComesAsLines) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_progress_lines";
  int status = 0;
  const std::string output = test::run_command(test::program() + " run " + short_scenario(0.3, 0.3, 0.03).string() +
                                                   " --settle-kinetic 1e-12 --out " + out.string(),
                                               &status);
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(output.find('\r'), std::string::npos) << output;
  const std::size_t header = output.find("Nishida A: 166 blocks"),
                    settling = output.find("  run: settling, 0.27 s of at most 0.30 s, kinetic energy "),
                    half = output.find("  run: 50 % of the shaking done, about ");
  ASSERT_NE(settling, std::string::npos) << output;
  ASSERT_NE(half, std::string::npos) << output;
  EXPECT_LT(header, settling) << output;
  EXPECT_LT(settling, half) << output;
  EXPECT_NE(output.find("(settled below 1e-12 J)\n"), std::string::npos) << output;
  EXPECT_NE(output.find("  run: 90 % of the shaking done"), std::string::npos) << output;
}

// A closed terminal (SIGHUP) stops a run as Ctrl-C does, its files whole and its summary
// saying so; under nohup the same signal leaves it running to its end.
TEST(Run, HangupStopsARunUnlessUnderNohup) {
  for (const bool nohup : {false, true}) {
    const auto out = std::filesystem::temp_directory_path() / (nohup ? "ishibashi_run_nohup" : "ishibashi_run_hangup");
    std::filesystem::remove_all(out);
    const std::string cmd = "bash -c '" + std::string(nohup ? "nohup " : "") + test::program() + " run --quiet " +
                            short_scenario(nohup ? 0.3 : 20.0).string() + " --out " + out.string() +
                            " > /dev/null 2>&1 & run=$!; while [ ! -f " + (out / "blocks.pvd").string() +
                            " ] && kill -0 $run 2> /dev/null; do sleep 0.05; done; sleep 0.5; kill -HUP $run && echo sent; "
                            "wait $run'";
    int status = 0;
    EXPECT_EQ(test::run_command(cmd, &status), "sent\n");  // while it ran (0.3 s of shaking: seconds)
    expect_valid_outputs(out);
    const std::string summary = test::text_of(out / "summary.json");
    EXPECT_NE(summary.find(nohup ? "\"finished\": true" : "\"interrupted\": true"), std::string::npos) << nohup << summary;
    EXPECT_EQ(status == 0, nohup) << status;
  }
}

TEST(Run, ProfileTableAndTraceOfAShortRun) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_run_trace";
  std::filesystem::remove_all(out);
  const auto trace = out.string() + ".json";
  int status = 0;
  const std::string output = test::run_command(test::program() + " run --quiet " + short_scenario(0.05).string() +
                                                   " --threads 2 --profile --trace " + trace + " --trace-steps 10:15 --out " +
                                                   out.string(), &status);
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("working  waiting   serial  imbalance"), std::string::npos) << output;
  for (const char* stage : {"\npose ", "\nnarrowphase+contact law ", "\n  narrowphase part ", "\n  contact law part ",
                            "\ngather+integrate+pose "})
    EXPECT_NE(output.find(stage), std::string::npos) << stage;
  EXPECT_NE(output.find("trace of 5 steps (10:15 asked)"), std::string::npos) << output;
  const nlohmann::json doc = nlohmann::json::parse(std::ifstream(trace));
  int steps = 0;
  for (const auto& e : doc["traceEvents"]) steps += e.value("cat", "") == "step";
  EXPECT_EQ(steps, 5);
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const nlohmann::json& shared = summary["stages"]["narrowphase+contact law"];
  EXPECT_GE(shared["imbalance"].get<double>(), 1.0);
  EXPECT_GT(shared["contact_law_work_s"].get<double>(), 0.0);
  EXPECT_LT(shared["contact_law_work_s"].get<double>(), shared["work_s"].get<double>());
  // The frames' share of the run's wall: some time, less than all of it.
  EXPECT_NE(output.find("\nframes: "), std::string::npos) << output;
  const double frames_s = summary["output_wall_s"].get<double>();
  EXPECT_GT(frames_s, 0.0);
  EXPECT_LT(frames_s, summary["wall_s"].get<double>());

  const std::string refused = test::run_command(test::program() + " run --quiet " + short_scenario(0.05).string() +
                                                    " --trace " + trace + " --trace-steps 15:10 --out " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(refused.find("--trace-steps 15:10: expected FROM:TO"), std::string::npos) << refused;
  std::filesystem::remove(trace);
}

// A number flag given nan or inf is refused before anything runs: CLI11's own checks
// compare, and every comparison with a NaN is false. So is a thread count beyond what a
// team holds.
TEST(Run, NanOrInfinityOnTheCommandLineIsRefused) {
  for (const char* flag : {"--dt nan", "--duration inf", "--start nan", "--dt-factor nan", "--settle-max -inf"}) {
    int status = 0;
    const std::string output = test::run_command(test::program() + " run --quiet " +
                                                     short_scenario(0.05).string() + " " + flag + " --out " +
                                                     (test::tmp_dir() / "ishibashi_run_nan").string(), &status);
    EXPECT_NE(status, 0) << flag;
    const std::string value = std::string(flag).substr(std::string(flag).find(' ') + 1);
    EXPECT_NE(output.find(value + " is not a finite number"), std::string::npos) << flag << ": " << output;
    EXPECT_FALSE(std::filesystem::exists(test::tmp_dir() / "ishibashi_run_nan")) << flag;
  }
  int status = 0;
  const std::string word = test::run_command(test::program() + " run --quiet " + short_scenario(0.05).string() +
                                                 " --duration ten", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(word.find("--duration: ten is not a number"), std::string::npos) << word;
  // More threads than a team holds (engine/cores.h kMaxThreads) is a typo, not a request.
  const std::string threads = test::run_command(test::program() + " run --quiet " + short_scenario(0.05).string() +
                                                    " --threads 1000 --out " + (test::tmp_dir() / "ishibashi_run_nan").string(),
                                                &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(threads.find("--threads: 1000 must be >= 0 and <= 256"), std::string::npos) << threads;
  // A flag's range is the scenario file's, upper bound included, and its message is one
  // short line (CLI11's own checks printed the largest double in 309 digits, and
  // --solve-tolerance took values the scenario file refuses).
  for (const auto& [flag, said] : {std::pair{"--duration -1", "--duration: -1 must be >= 0\n"},
                                   std::pair{"--solve-tolerance 0.9", "--solve-tolerance: 0.9 must be > 0 and <= 0.5\n"},
                                   std::pair{"--output-interval 0", "--output-interval: 0 must be > 0\n"}}) {
    const std::string refused = test::run_command(test::program() + " run --quiet " + short_scenario(0.05).string() + " " +
                                                      flag + " --out " + (test::tmp_dir() / "ishibashi_run_nan").string(),
                                                  &status);
    EXPECT_NE(status, 0) << flag;
    EXPECT_NE(refused.find(said), std::string::npos) << refused;
  }
}


// `build --export` writes the blocks as a mesh that reads back block for block (model A:
// 165 stones and the ground slab), into a folder it makes (the output folder, as a user
// gives it: it said "a full disk or no permission?" where the folder was not there yet),
// and a name CGAL cannot write is refused before the validation, not after it.
TEST(Run, BuildExportsTheBlocksAndRefusesAnUnknownMeshFormatAtOnce) {
  const std::string out = (test::tmp_dir() / "ishibashi_export").string();
  std::filesystem::remove_all(out);
  const auto mesh = std::filesystem::path(out) / "blocks.obj";
  int status = 0;
  const std::string model = (kRoot / "models/nishida_a.toml").string();
  const std::string built = test::run_command(test::program() + " build " + model + " --export " + mesh.string() + " --out " + out, &status);
  ASSERT_EQ(status, 0) << built;
  EXPECT_EQ(read_block_file(mesh).size(), 166u);
  const std::string refused = test::run_command(test::program() + " build " + model + " --export blocks.xyz", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(refused.find("--export: blocks.xyz must end in .off, .obj or .stl"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("validation"), std::string::npos) << refused;
}

// A model whose blocks touch nothing has no contact to set the time step: a run says so
// and asks for dt_s (it said "dt must be a positive number"), and `build` prints no limit
// (it printed "inf s, set by block -1", reading a mass at index -1).
TEST(Run, ModelWithoutContactsAsksForATimeStep) {
  const auto dir = test::tmp_dir() / "ishibashi_no_contacts";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cube.off") << "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                                  << "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  std::ofstream(dir / "cube.toml") << "[model]\nname = \"cube\"\n[import]\nfiles = [\"cube.off\"]\n";
  std::ofstream(dir / "shake.toml") << "[model]\nfile = \"cube.toml\"\n[run]\nduration_s = 0.01\n[ground_motion]\nx = { file = \""
                                    << (kRoot / "data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM090.AT2").string() << "\" }\n";
  int status = 0;
  const std::string run = test::run_command(test::program() + " run --quiet " + (dir / "shake.toml").string() +
                                                " --out " + (dir / "out").string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(run.find("shake.toml: no two blocks of its model touch at the start, so no contact sets the time step; set dt_s"),
            std::string::npos) << run;
  const std::string build = test::run_command(test::program() + " build " + (dir / "cube.toml").string() +
                                                  " --out " + (dir / "build").string(), &status);
  EXPECT_EQ(status, 0) << build;
  EXPECT_NE(build.find("no two blocks touch, so no contact sets a stability limit"), std::string::npos) << build;
  EXPECT_EQ(build.find("inf s"), std::string::npos) << build;
  std::filesystem::remove_all(dir);
}


// The run's header gives the shaking's peaks by component, the first check of a record's
// units; a record whose unit is wrong (gal values read as g: a peak of 306 g) is warned of.
// A 1 Hz sine of 300 gal, 10 periods at 0.01 s, from its first crest (a short window left
// uncorrected: a baseline correction takes away a short window's mean): its peak
// acceleration is 3 m/s^2 (0.306 g).
TEST(Run, HeaderGivesTheShakingsPeaksAndWarnsOfAWrongUnit) {
  const auto dir = test::tmp_dir() / "ishibashi_run_peaks";
  std::filesystem::create_directories(dir);
  {
    std::ofstream sine(dir / "sine.txt");
    for (int k = 0; k <= 1000; ++k) sine << 300 * std::sin(2 * M_PI * k * 0.01) << "\n";
  }
  for (const std::string unit : {"gal", "g"}) {
    std::ofstream(dir / (unit + ".toml")) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string()
                                          << "\"\n[run]\nsettle_max_s = 0.01\nduration_s = 0.01\n"
                                          << "[ground_motion]\nstart_s = 0.25\nbaseline_correction = false\n"
                                          << "x = { file = \"sine.txt\", format = \"columns\", dt_s = 0.01, unit = \"" << unit << "\" }\n";
    int status = 0;
    const std::string run = test::run_command(test::program() + " run --quiet " + (dir / (unit + ".toml")).string() +
                                                  " --out " + (dir / unit).string(), &status);
    ASSERT_EQ(status, 0) << run;
    if (unit == "gal") {
      EXPECT_NE(run.find("  peak ground acceleration x 3, y 0, z 0 m/s^2 (0.306, 0, 0 g)"), std::string::npos) << run;
      const nlohmann::json peaks = nlohmann::json::parse(test::text_of(dir / unit / "summary.json"))["ground_motion"];
      EXPECT_NEAR(peaks["peak_acceleration_m_s2"][0].get<double>(), 3.0, 1e-9) << peaks;
      EXPECT_EQ(peaks["peak_acceleration_m_s2"][2].get<double>(), 0.0) << peaks;
      EXPECT_EQ(run.find("warning"), std::string::npos) << run;
    } else {
      EXPECT_NE(run.find("warning: the records' peak ground acceleration of 300 g is above any earthquake recorded (about "
                         "4 g): check each record's unit in " + (dir / "g.toml").string()),
                std::string::npos) << run;
    }
  }
  std::filesystem::remove_all(dir);
}

// Where the mortar lies (mortar_parts) is said in the run's header and summary.json; a
// dry run says nothing of mortar; a part the bridge lacks is refused naming the model file.
TEST(Run, HeaderAndSummarySayWhereTheMortarLies) {
  const auto dir = test::tmp_dir() / "ishibashi_run_mortar_parts";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "still.txt") << "0\n0\n0\n0\n0\n";
  for (const std::string mortar : {"", "mortar_pa = 2e5\n", "mortar_pa = 2e5\nmortar_parts = [\"ring\"]\n"}) {
    std::ofstream(dir / "run.toml") << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\n"
                                    << mortar << "[run]\nsettle_max_s = 0.01\nduration_s = 0.01\n[ground_motion]\n"
                                    << "x = { file = \"still.txt\", format = \"columns\", dt_s = 0.01, unit = \"g\" }\n";
    int status = 0;
    const std::string run = test::run_command(test::program() + " run --quiet --no-report " + (dir / "run.toml").string() +
                                                  " --out " + (dir / "out").string(), &status);
    ASSERT_EQ(status, 0) << run;
    const nlohmann::json summary = nlohmann::json::parse(test::text_of(dir / "out" / "summary.json"));
    if (mortar.empty()) {
      EXPECT_EQ(run.find("  mortar "), std::string::npos) << run;
      EXPECT_EQ(summary["mortar_pa"].get<double>(), 0.0);
    } else if (mortar.find("mortar_parts") == std::string::npos) {
      EXPECT_NE(run.find("  mortar f_t = c = 2e+05 Pa at every stone joint in contact, set once the bridge has settled\n"),
                std::string::npos) << run;
      EXPECT_EQ(summary["mortar_parts"].size(), 5u) << summary["mortar_parts"];  // every stone part
    } else {
      EXPECT_NE(run.find("  mortar f_t = c = 2e+05 Pa at the stone joints in contact within ring, set once the bridge has settled\n"),
                std::string::npos) << run;
      EXPECT_EQ(summary["mortar_parts"], nlohmann::json::array({"ring"})) << summary["mortar_parts"];
    }
  }
  std::ofstream(dir / "run.toml") << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string()
                                  << "\"\nmortar_pa = 2e5\nmortar_parts = [\"ring\", \"wall\"]\n[ground_motion]\n"
                                  << "x = { file = \"still.txt\", format = \"columns\", dt_s = 0.01, unit = \"g\" }\n";
  int status = 0;
  const std::string refused = test::run_command(test::program() + " run --quiet " + (dir / "run.toml").string() + " --out " +
                                                    (dir / "refused").string(), &status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << refused;
  EXPECT_NE(refused.find("nishida_a.toml: mortar_parts (the model's [bridge] or the scenario's [model]) lists \"wall\", "
                         "but the bridge has no stone block of that part"), std::string::npos) << refused;
  std::filesystem::remove_all(dir);
}

// A model with tie rods: the header says what they are, ties.pvd holds a line per rod in
// every frame with its tension, summary.json the rods' demand and history.csv their columns.
TEST(Run, TieRodsAreDescribedDrawnAndSummed) {
  const auto dir = test::tmp_dir() / "ishibashi_run_ties";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "still.txt") << "0\n0\n0\n0\n0\n";
  // Model A's ring with a rod across its width through the crown voussoirs of the two face courses.
  std::ofstream(dir / "tied.toml") << test::text_of(kRoot / "models/nishida_a.toml")
                                   << "\n[[tie]]\nfrom = [0, -1.5, 5.08]\nto = [0, 1.5, 5.08]\ndiameter_m = 0.03\n";
  std::ofstream(dir / "run.toml") << "[model]\nfile = \"tied.toml\"\n[run]\nsettle_max_s = 0.02\nduration_s = 0.02\n"
                                  << "output_interval_s = 0.01\n[ground_motion]\n"
                                  << "x = { file = \"still.txt\", format = \"columns\", dt_s = 0.01, unit = \"g\" }\n";
  int status = 0;
  const std::string run = test::run_command(test::program() + " run --quiet --no-report " + (dir / "run.toml").string() +
                                                " --out " + (dir / "out").string(), &status);
  ASSERT_EQ(status, 0) << run;
  EXPECT_NE(run.find("  1 tie rod, d = 30 mm, f_y = 235 MPa, yield force 166 kN\n"), std::string::npos) << run;
  const auto blocks = read_pvd(dir / "out" / "blocks.pvd"), ties = read_pvd(dir / "out" / "ties.pvd");
  ASSERT_EQ(ties.size(), blocks.size());
  vtkUnstructuredGrid* g = read_vtu(ties.back().file);
  ASSERT_EQ(g->GetNumberOfCells(), 1);
  EXPECT_EQ(g->GetCellType(0), VTK_LINE);
  double a[3], b[3];
  g->GetPoint(0, a), g->GetPoint(1, b);
  EXPECT_NEAR(std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]), 3.0, 1e-3);  // its anchors, where they were put
  for (const char* name : {"tie_id", "block_a", "block_b", "tension_n", "peak_tension_n", "plastic_elongation_m", "yielded"})
    EXPECT_NE(g->GetCellData()->GetArray(name), nullptr) << name;
  const double peak_in_file = g->GetCellData()->GetArray("peak_tension_n")->GetComponent(0, 0);
  g->Delete();
  const nlohmann::json summary = nlohmann::json::parse(test::text_of(dir / "out" / "summary.json"));
  EXPECT_EQ(summary["tie_rods"], 1);
  EXPECT_EQ(summary["ties_yielded"], 0);
  EXPECT_DOUBLE_EQ(summary["peak_tie_tension_n"].get<double>(), peak_in_file);
  EXPECT_EQ(summary["ties"]["peak_tension_by_rod_n"], nlohmann::json::array({peak_in_file}));
  EXPECT_NEAR(summary["ties"]["yield_force_by_rod_n"][0].get<double>(), 2.35e8 * M_PI / 4 * 0.03 * 0.03, 1e-6);  // f_y A
  std::ifstream history(dir / "out" / "history.csv");
  std::string header;
  std::getline(history, header);
  for (const char* column : {",tie_yield_j,", ",ties_yielded,", ",largest_tie_tension_n"})
    EXPECT_NE(header.find(column), std::string::npos) << column;
  // view.pvsm draws the rods from ties.pvd, and plays its frames with the others.
  const std::string pvsm = test::text_of(dir / "out" / "view.pvsm");
  EXPECT_NE(pvsm.find("value=\"ties.pvd\""), std::string::npos);
  EXPECT_NE(pvsm.find("name=\"tie rods\""), std::string::npos);
  std::filesystem::remove_all(dir);
}

// More threads than usable cores are warned of (they wait their turn at every step); as
// many as there are, not.
TEST(Run, MoreThreadsThanCoresAreWarnedOf) {
  const int cores = usable_cores();
  for (const int threads : {cores, cores + 1}) {
    int status = 0;
    const std::string run = test::run_command(test::program() + " run --quiet --no-report " +
                                                  (kRoot / "scenarios/nishida_a_kobe_dry.toml").string() +
                                                  " --settle-max 0.01 --duration 0.01 --threads " + std::to_string(threads) +
                                                  " --out " + (test::tmp_dir() / "ishibashi_threads").string(), &status);
    ASSERT_EQ(status, 0) << run;
    EXPECT_EQ(run.find("warning: " + std::to_string(threads) + " threads on " + std::to_string(cores) + " usable cores") !=
                  std::string::npos,
              threads > cores) << run;
  }
}

// A scenario without [ground_motion] is refused naming it, before its model is built (it
// said "ground motion: no component given", naming no file, once the model was built).
TEST(Run, ScenarioWithoutGroundMotionIsRefusedNamingIt) {
  const auto file = test::tmp_dir() / "ishibashi_no_motion.toml";
  std::ofstream(file) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\n[run]\nduration_s = 1\n";
  int status = 0;
  const std::string run = test::run_command(test::program() + " run --quiet " + file.string() + " --out " +
                                                (test::tmp_dir() / "ishibashi_no_motion").string(), &status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << run;
  EXPECT_NE(run.find("ishibashi_no_motion.toml: no ground motion to shake with: [ground_motion] x, y or z"), std::string::npos)
      << run;
}

// A duration past the record's end is cut to the record, and the run says so.
TEST(Run, DurationPastTheRecordsEndIsSaid) {
  int status = 0;
  const auto out = test::tmp_dir() / "ishibashi_run_past_end";
  const std::string output = test::run_command(test::program() + " run --quiet " + short_scenario(1.0, 0.01).string() +
                                                   " --start 149.97 --out " + out.string(), &status);
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("the record ends 0.01 s after start_s: the run shakes for that long, not the 1.00 s asked"),
            std::string::npos) << output;
  std::filesystem::remove_all(out);
}

// `--stop-at collapse`: the run's last line says it stopped at its collapse only when it did.
// A run whose record ends at the very frame that first finds the collapse ran its whole
// record, and says "done" (summary.json: not stopped early), though it collapsed. (Without
// the baseline correction, which fits its constant to the whole window: a shorter record
// is then the longer one's beginning, the same motion step for step.)
TEST(Run, StopAtCollapseSaysStoppedThereOnlyWhenTheRunStopped) {
  std::string text = test::text_of(kRoot / "scenarios/examples/stack_of_three_tied_kobe.toml");
  for (std::size_t at; (at = text.find("\"../../")) != std::string::npos;) text.replace(at, 7, "\"" + kRoot.string() + "/");
  const auto scenario = std::filesystem::temp_directory_path() / "ishibashi_stop_at_tied.toml";
  std::ofstream(scenario) << text << "baseline_correction = false\n";  // [ground_motion], the file's last table
  auto run = [&](const std::string& name, const std::string& options, nlohmann::json* summary) {
    const auto out = std::filesystem::temp_directory_path() / ("ishibashi_stop_at_" + name);
    std::filesystem::remove_all(out);
    int status = 0;
    const std::string said = test::run_command(
        test::program() + " run " + scenario.string() + " --threads 1 --no-report --stop-at collapse " + options + " --out " + out.string(),
        &status);
    EXPECT_EQ(status, 0) << said;
    *summary = nlohmann::json::parse(test::text_of(out / "summary.json"));
    std::filesystem::remove_all(out);
    return said;
  };
  nlohmann::json stopped, ended;
  const std::string first = run("stopped", "", &stopped);
  ASSERT_TRUE(stopped["collapse"].get<bool>()) << first;  // the tied stack topples within its 3 s
  EXPECT_TRUE(stopped["stopped_early"].get<bool>());
  EXPECT_NE(first.find("collapse, stopped there (--stop-at collapse), after"), std::string::npos) << first;
  const double at_s = stopped["shaking_time_s"].get<double>();
  ASSERT_LT(at_s, 2.9);
  char duration[32];
  std::snprintf(duration, sizeof duration, "--duration %.9f", at_s + 1e-7);  // dt = 9.9e-6 s: the same step count
  const std::string second = run("ended", duration, &ended);
  ASSERT_TRUE(ended["collapse"].get<bool>()) << second;
  EXPECT_EQ(ended["steps"], stopped["steps"]);
  EXPECT_FALSE(ended["stopped_early"].get<bool>());
  EXPECT_EQ(second.find("stopped there"), std::string::npos) << second;
  EXPECT_NE(second.find("done after"), std::string::npos) << second;
}

}  // namespace
}  // namespace ishibashi
