// Checkpoint and restart of `ishibashi run`: a run killed (SIGKILL) at a random moment and
// resumed from its last checkpoint ends bit-identical to a run never stopped, with the
// same history and series; a checkpoint of another build or of changed inputs is refused.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdint>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/model/fingerprint.h"
#include "analysis/run/checkpoint.h"
#include "analysis/run/run_recorder.h"
#include "engine/world.h"
#include "geometry/shapes.h"
#include "command_line.h"
#include "io/run_settings.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, kRoot, tmp_dir

std::string summary_field(const std::filesystem::path& out, const std::string& key) {
  std::istringstream summary(text_of(out / "summary.json"));
  std::string line;
  while (std::getline(summary, line))
    if (line.find("\"" + key + "\"") != std::string::npos) return line.substr(line.find(':') + 2);
  return "";
}

// Model A from 7.5 s of the Kobe record (the strongest pulses), 0.4 s of shaking.
// `model`: another model file.
std::filesystem::path scenario(const std::string& name, double settle_max_s = 1.0, double duration_s = 0.4,
                               const std::filesystem::path& model = kRoot / "models/nishida_a.toml") {
  const auto f = tmp_dir() / name;
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  std::ofstream(f) << "[model]\nfile = \"" << model.string() << "\"\n"
                   << "[run]\nsettle_max_s = " << settle_max_s << "\nsettle_kinetic_j = 0.01\nduration_s = " << duration_s << "\n"
                   << "[ground_motion]\nstart_s = 7.5\n"
                   << "x = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n"
                   << "y = { file = \"" << (kobe / "RSN1106_KOBE_KJM000.AT2").string() << "\" }\n"
                   << "z = { file = \"" << (kobe / "RSN1106_KOBE_KJM-UP.AT2").string() << "\" }\n";
  return f;
}

const std::string kRun = test::program() + " run --quiet --no-report ";  // a picture costs a second a run

// Runs the scenario whole, and again killed with SIGKILL at a random moment after its
// first checkpoint (a random part, up to max_part, of the whole run's wall time later, so
// that a loaded machine only stretches the test) and resumed; both must end the same.
// `options`: more `run` options. `while_shaking`: the random moment counts from the
// history's second row of shaking instead (checkpoints are written at the frames, each
// after its row: the first row's lies before the kill), so that the run resumes with the
// ground moving, where the ground's work over the step across the checkpoint needs its
// forces at the pose before.
void expect_killed_run_resumes_bit_identical(const std::string& name, const std::string& options, double max_part,
                                             bool while_shaking = false,
                                             const std::filesystem::path& model = kRoot / "models/nishida_a.toml") {
  const auto file = scenario(name + ".toml", 1.0, 0.4, model);
  const auto whole = tmp_dir() / (name + "_whole"), killed = tmp_dir() / (name + "_killed");
  std::filesystem::remove_all(whole);
  std::filesystem::remove_all(killed);
  int status = 0;
  const auto started = std::chrono::steady_clock::now();
  ASSERT_EQ((run_command(kRun + file.string() + options + " --out " + whole.string(), &status), status), 0);
  const double whole_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  std::random_device device;
  const unsigned seed = device();
  std::mt19937 random(seed);
  const double kill_after_s = std::uniform_real_distribution<double>(0.0, max_part * whole_s)(random);
  SCOPED_TRACE("killed " + std::to_string(kill_after_s) + " s after " + (while_shaking ? "its second row of shaking" : "its first checkpoint") +
               " (seed " + std::to_string(seed) + ")");
  const std::string checkpoint = (killed / "checkpoint.bin").string();
  const std::string history = (killed / "history.csv").string();
  const std::string started_when = while_shaking ? "[ $(cat " + history + " 2> /dev/null | grep -c ,shake,) -lt 2 ]" : "[ ! -f " + checkpoint + " ]";
  run_command("bash -c '" + kRun + file.string() + options + " --checkpoint-every 0.05 --out " + killed.string() +
                  " & run=$!; while " + started_when +
                  " && kill -0 $run 2> /dev/null; do sleep 0.02; done; sleep " + std::to_string(kill_after_s) +
                  "; kill -KILL $run; wait $run'",
              &status);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGKILL) << "the run was not killed: status " << status;
  ASSERT_TRUE(std::filesystem::exists(killed / "checkpoint.bin"));
  const std::string resumed = run_command(kRun + "--resume " + killed.string(), &status);
  ASSERT_EQ(status, 0) << resumed;

  EXPECT_EQ(summary_field(killed, "state_hash"), summary_field(whole, "state_hash"));
  EXPECT_EQ(summary_field(killed, "energy_balance_error_j"), summary_field(whole, "energy_balance_error_j"));
  EXPECT_EQ(summary_field(killed, "finished"), "true,");
  EXPECT_EQ(text_of(killed / "history.csv"), text_of(whole / "history.csv"));
  // How it fails: the falls and the ring's hinges noted before the kill come back with the checkpoint.
  EXPECT_EQ(nlohmann::json::parse(text_of(killed / "summary.json"))["how_it_fails"],
            nlohmann::json::parse(text_of(whole / "summary.json"))["how_it_fails"]);
  EXPECT_EQ(text_of(killed / "blocks.pvd"), text_of(whole / "blocks.pvd"));
  EXPECT_EQ(text_of(killed / "contacts.pvd"), text_of(whole / "contacts.pvd"));
  if (std::filesystem::exists(whole / "ties.pvd")) {
    EXPECT_EQ(text_of(killed / "ties.pvd"), text_of(whole / "ties.pvd"));
    EXPECT_EQ(summary_field(killed, "largest_plastic_elongation_m"), summary_field(whole, "largest_plastic_elongation_m"));
  }
}

TEST(Checkpoint, RunKilledAtARandomMomentResumesBitIdentical) {
  expect_killed_run_resumes_bit_identical("ishibashi_checkpoint", "", 0.4);
}

// A model with a tie rod: ties.pvd's frames resume with the others' (the rod's state:
// Checkpoint.TieRodStateRoundTripsBitIdentical). A 4 mm rod across model A's crown, which
// these pulses make yield.
TEST(Checkpoint, RunWithATieRodResumesBitIdentical) {
  const auto model = tmp_dir() / "ishibashi_checkpoint_tied_model.toml";
  std::ofstream(model) << text_of(kRoot / "models/nishida_a.toml")
                       << "\n[[tie]]\nfrom = [0, -1.5, 5.08]\nto = [0, 1.5, 5.08]\ndiameter_m = 0.004\n";
  expect_killed_run_resumes_bit_identical("ishibashi_checkpoint_tied", "", 0.4, /*while_shaking=*/false, model);
}

// A yielded rod's state (plastic elongation, peak tension) and the work its yielding took,
// written and read back into a fresh world, go on bit-identically: two stones in zero
// gravity sent apart on a rod that yields.
TEST(Checkpoint, TieRodStateRoundTripsBitIdentical) {
  auto world = [] {
    ModelBuilder b;
    b.set_gravity(Vec3::Zero());
    const int mat = b.add_material(Material{});
    for (double x : {-1.5, 1.5}) {
      const Polyhedron cube = make_box(Vec3(x, 0, 0), Vec3(1, 1, 1));
      b.add_block(cube.vertices, cube.faces, mat);
    }
    b.add_tie(Vec3(-1.2, 0.2, 0), Vec3(1.2, 0.2, 0), 1e-4, 2e11, 5e7);  // yields at 5 kN
    return std::make_unique<World>(b.build(), 1e-5);
  };
  auto whole = world();
  whole->state().velocity[0] = Vec3(-0.05, 0, 0);
  whole->state().velocity[1] = Vec3(0.05, 0.01, 0);
  whole->run(1500);  // 15 ms: past the yield, rod still taut
  ASSERT_GT(whole->state().tie_plastic_m[0], 0.0);
  std::stringstream bytes;
  CheckpointWriter out(bytes);
  write_state(out, whole->state());
  auto resumed = world();
  CheckpointReader in(bytes);
  read_state(in, resumed->state());
  whole->run(1500);
  resumed->run(1500);
  EXPECT_EQ(resumed->state_hash(), whole->state_hash());
  EXPECT_EQ(resumed->state().tie_plastic_m, whole->state().tie_plastic_m);
  EXPECT_EQ(resumed->state().tie_peak_tension_n, whole->state().tie_peak_tension_n);
  EXPECT_EQ(resumed->state().energy.tie_yield_j, whole->state().energy.tie_yield_j);
  // The run's result counts the rod as yielded, its peak tension its yield force f_y A.
  Joints joints = find_original_joints(whole->state());
  SeismicRunResult result;
  take_counts(whole->model(), count_damage(whole->model(), whole->state(), JointThresholds{}, joints), result);
  EXPECT_EQ(result.tie_rods, 1);
  EXPECT_EQ(result.ties_yielded, 1);
  EXPECT_NEAR(result.peak_tie_tension_n, 1e-4 * 5e7, 1e-9);
}

// The caps are part of the state, and the resumed run keeps --damping capped (and its
// larger step) from the checkpoint.
TEST(Checkpoint, RunWithCappedDashpotsResumesBitIdentical) {
  expect_killed_run_resumes_bit_identical("ishibashi_checkpoint_capped", " --damping capped", 0.4);
}

// The implicit dashpots' first guess (last step's solution) is part of the state: without
// it, the resumed run's solves would stop at other iterates.
TEST(Checkpoint, RunWithImplicitDashpotsResumesBitIdentical) {
  expect_killed_run_resumes_bit_identical("ishibashi_checkpoint_implicit", " --damping implicit", 0.4);
}

// Killed while the ground moves: the resumed run's first step takes the ground's contact
// forces at the pose before from the checkpoint (the trapezoid rule of its work).
TEST(Checkpoint, RunKilledWhileShakingResumesBitIdentical) {
  expect_killed_run_resumes_bit_identical("ishibashi_checkpoint_shaking", "", 0.3, /*while_shaking=*/true);
}

// A resumed run's wall time is the work of every part: stopped (SIGINT, which writes a
// checkpoint) once five of its eight frames of shaking are written, the first part is
// the longer, and the resumed run's summary must count it. Its --profile and --trace
// time the threads of the steps it runs itself, though the first part's were not timed.
TEST(Checkpoint, ResumedRunsWallTimeCountsEveryPart) {
  const auto file = scenario("ishibashi_checkpoint_wall.toml", 0.1, 0.4);
  const auto out = tmp_dir() / "ishibashi_cp_wall";
  std::filesystem::remove_all(out);
  int status = 0;
  run_command("bash -c '" + kRun + file.string() + " --checkpoint-wall 1000 --out " + out.string() +
                  " & run=$!; while [ $(cat " + (out / "history.csv").string() +
                  " 2> /dev/null | grep -c ,shake,) -lt 5 ] && kill -0 $run 2> /dev/null; do sleep 0.02; done; kill -INT $run; wait $run'",
              &status);
  ASSERT_TRUE(std::filesystem::exists(out / "checkpoint.bin")) << "the run ended before it was stopped";
  const double first_part_s = std::stod(summary_field(out, "wall_s"));
  const long first_steps = std::stol(summary_field(out, "steps"));
  const auto trace = tmp_dir() / "ishibashi_cp_wall_trace.json";
  const std::string resumed =
      run_command(kRun + "--resume " + out.string() + " --profile --trace " + trace.string() + " --trace-steps " +
                      std::to_string(first_steps + 2) + ":" + std::to_string(first_steps + 5), &status);
  ASSERT_EQ(status, 0) << resumed;
  EXPECT_EQ(summary_field(out, "finished"), "true,");
  EXPECT_GT(std::stod(summary_field(out, "wall_s")), first_part_s);

  const long steps = std::stol(summary_field(out, "steps"));
  EXPECT_NE(resumed.find("the " + std::to_string(steps - first_steps) + " steps since the checkpoint (step " +
                         std::to_string(first_steps) + "):"), std::string::npos) << resumed;
  EXPECT_EQ(resumed.find("nan"), std::string::npos) << resumed;  // team times of untimed steps divided by none
  const std::string timeline = text_of(trace);
  EXPECT_EQ(count_of(timeline, "\"cat\": \"step\""), 3) << timeline.substr(0, 2000);
  EXPECT_GE(count_of(timeline, "\"name\": \"narrowphase+contact law\""), 3) << timeline.substr(0, 2000);
  // The first part's steps were not timed: the whole run's summary leaves the team's split out.
  EXPECT_EQ(text_of(out / "summary.json").find("imbalance"), std::string::npos);
}

// Ctrl-C while settling stops the run at once (it looks at a stop request every few
// hundred steps, not only at the settling's 0.05 s checks), says so, and writes no shaking
// into summary.json; a checkpoint of the settling is kept.
TEST(Checkpoint, RunStoppedWhileSettlingSaysSoAndKeepsACheckpoint) {
  const auto file = scenario("ishibashi_checkpoint_settling.toml", 1.0, 0.4);
  const auto out = tmp_dir() / "ishibashi_cp_settling";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string text =
      run_command("bash -c '" + kRun + file.string() + " --checkpoint-wall 1000 --out " + out.string() + " & run=$!; until [ -f " +
                      (out / "blocks.pvd").string() + " ]; do sleep 0.02; done; kill -INT $run; wait $run'",
                  &status);
  EXPECT_NE(text.find("interrupted while settling"), std::string::npos) << text;
  EXPECT_EQ(summary_field(out, "shaking_time_s"), "0.0,") << text_of(out / "summary.json");
  EXPECT_TRUE(std::filesystem::exists(out / "checkpoint.bin"));
}

// A finished run's last checkpoint lies before its end: a resume says the run finished and
// leaves its outputs as they are, where it went on from that checkpoint and wrote the end again.
TEST(Checkpoint, ResumeOfAFinishedRunSaysSoAndWritesNothing) {
  const auto file = scenario("ishibashi_checkpoint_finished.toml", 0.1, 0.1);
  const auto out = tmp_dir() / "ishibashi_cp_finished";
  std::filesystem::remove_all(out);
  int status = 0;
  ASSERT_EQ((run_command(kRun + file.string() + " --checkpoint-every 0.05 --out " + out.string(), &status), status), 0);
  ASSERT_TRUE(std::filesystem::exists(out / "checkpoint.bin"));
  const auto written = std::filesystem::last_write_time(out / "history.csv");
  const std::string message = run_command(kRun + "--resume " + out.string(), &status);
  EXPECT_EQ(status, 0) << message;
  EXPECT_NE(message.find("the run there finished (0.10 s of shaking, summary.json): nothing to resume"), std::string::npos)
      << message;
  EXPECT_EQ(std::filesystem::last_write_time(out / "history.csv"), written);
}

TEST(Checkpoint, CheckpointOfAnotherBuildOrOfChangedInputsIsRefused) {
  const auto file = scenario("ishibashi_checkpoint_refused.toml", 0.1, 20.0);
  const auto out = tmp_dir() / "ishibashi_cp_refused";
  std::filesystem::remove_all(out);
  int status = 0;
  // A run stopped by SIGINT writes a checkpoint too: SIGINT 1 s after the run's first frame
  // (a fixed 3 s stopped a loaded machine's run before it began, and let a quiet machine's
  // 0.4 s run end before the signal).
  run_command("bash -c '" + kRun + file.string() + " --checkpoint-wall 1000 --out " + out.string() + " & run=$!; while [ ! -f " +
                  (out / "blocks.pvd").string() + " ] && kill -0 $run 2> /dev/null; do sleep 0.05; done; sleep 1; kill -INT $run; wait $run'",
              &status);
  ASSERT_TRUE(std::filesystem::exists(out / "checkpoint.bin"));
  const std::string good = text_of(out / "checkpoint.bin");

  std::string other_build = good;
  const std::string magic = "ishibashi checkpoint 21\n";
  other_build[magic.size() + 8] ^= 1;  // the program's fingerprint
  std::ofstream(out / "checkpoint.bin", std::ios::binary) << other_build;
  std::string message = run_command(kRun + "--resume " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(message.find("written by another build of ishibashi"), std::string::npos) << message;

  // The header (magic, program and inputs, scenario path, each run setting of
  // io/run_settings.h, the ensemble member), then the body's checksum, then the body, whose
  // first byte is the phase flag. Any byte of the body changed: refused by the checksum.
  std::size_t settings_bytes = 0;
  for_each_run_setting([&](const SettingInfo&, auto member) { settings_bytes += sizeof(RunSettings{}.*member); });
  const std::size_t header =
      8 + magic.size() + 16 + 8 + std::filesystem::absolute(file).string().size() + settings_bytes + sizeof(int);
  const std::size_t body = header + 8;
  for (const std::size_t at : {body, body + (good.size() - body) / 2, good.size() - 1}) {
    std::string damaged = good;
    damaged[at] ^= 1;
    std::ofstream(out / "checkpoint.bin", std::ios::binary) << damaged;
    message = run_command(kRun + "--resume " + out.string(), &status);
    EXPECT_NE(status, 0) << "byte " << at;
    EXPECT_NE(message.find("damaged checkpoint (its contents differ from the checksum written with them)"), std::string::npos)
        << "byte " << at << ": " << message;
  }
  // A body that matches its checksum is still read with care: a flag byte other than 0 or 1.
  std::string bad_flag = good;
  bad_flag[body] = 7;
  const std::uint64_t checksum = fnv1a(bad_flag.substr(body));
  bad_flag.replace(header, 8, reinterpret_cast<const char*>(&checksum), 8);
  std::ofstream(out / "checkpoint.bin", std::ios::binary) << bad_flag;
  message = run_command(kRun + "--resume " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(message.find("damaged checkpoint (a flag byte of 7 where 0 or 1 belongs)"), std::string::npos) << message;

  std::ofstream(out / "checkpoint.bin", std::ios::binary) << good;
  std::ofstream(file, std::ios::app) << "# edited\n";
  message = run_command(kRun + "--resume " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(message.find("changed since the checkpoint was written"), std::string::npos) << message;

  std::ofstream(out / "checkpoint.bin", std::ios::binary) << good.substr(0, good.size() / 2);
  message = run_command(kRun + "--resume " + out.string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(message.find("checkpoint"), std::string::npos) << message;
}

}  // namespace
}  // namespace ishibashi
