// ishibashi: 3-D distinct element analysis of masonry stone arch bridges.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <filesystem>
#include <string>

#include "apps/build_command.h"
#include "apps/demo.h"
#include "apps/modal_command.h"
#include "apps/run_command.h"
#include "apps/run_setting_flags.h"
#include "apps/study_command.h"
#include "apps/sweep_command.h"
#include "engine/cores.h"
#include "engine/model.h"
#include "io/model_file.h"

namespace {

// The `demo` command, its options read into `demo`.
CLI::App* add_demo_command(CLI::App& app, ishibashi::DemoOptions& demo) {
  CLI::App* demo_cmd = app.add_subcommand("demo", "A masonry wall on a shaking or tilting base, written for ParaView");
  demo_cmd->add_option("--scene", demo.scene, "shake or tilt")->check(CLI::IsMember({"shake", "tilt"}));
  demo_cmd->add_option("--out", demo.out, "output folder (blocks.pvd and .vtu files)");
  demo_cmd->add_option("--duration", demo.duration_s, "simulated time, s")->check(ishibashi::number_in(0, INFINITY, true));
  demo_cmd->add_option("--fps", demo.frames_per_s, "output frames per simulated second")->check(ishibashi::number_in(0, INFINITY, true));
  demo_cmd->add_option("--dt", demo.dt_s, "time step, s")->check(ishibashi::number_in(0, INFINITY, true));
  demo_cmd->add_option("--courses", demo.courses, "courses of stones")->check(ishibashi::number_in(1, 200));
  demo_cmd->add_option("--stones", demo.stones_per_course, "stones per course")->check(ishibashi::number_in(2, 500));
  return demo_cmd;
}

// The `build` command, its options read into `build`.
CLI::App* add_build_command(CLI::App& app, ishibashi::BuildOptions& build) {
  CLI::App* build_cmd = app.add_subcommand("build", "Generate a bridge from a model file, validate it, write it for ParaView");
  build_cmd->add_option("model_file", build.model_file, "model file (TOML), e.g. models/nishida_b.toml")->required();
  build_cmd->add_option("--out", build.out, "output folder for the .vtu");
  // Checked before the minutes of validation that come before the export.
  const CLI::Validator mesh_file(
      [](std::string& name) {
        std::string ext = std::filesystem::path(name).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        return ext == ".off" || ext == ".obj" || ext == ".stl" ? std::string() : name + " must end in .off, .obj or .stl";
      },
      "MESH");
  build_cmd->add_option("--export", build.export_file, "also write the blocks to this .off, .obj or .stl file")->check(mesh_file);
  ishibashi::add_run_setting_flags(build_cmd, build.overrides, {"joint_rule", "subdivision", "shear_spring"});
  return build_cmd;
}

// The `run` command, its options read into `run`.
CLI::App* add_run_command(CLI::App& app, ishibashi::RunOptions& run) {
  CLI::App* run_cmd = app.add_subcommand("run", "Settle a bridge under gravity, then shake it with a recorded ground motion");
  CLI::Option* run_scenario_file =
      run_cmd->add_option("scenario", run.scenario, "scenario file (TOML), e.g. scenarios/nishida_a_kobe_dry.toml");
  run_cmd->add_option("--out", run.out, "output folder (default: out/<scenario name>)");
  run_cmd->add_flag("--profile", run.profile,
                    "print the time spent in each stage of the step, and how the threads spent it (working, waiting, imbalance)");
  run_cmd->add_option("--trace", run.trace,
                      "write a timeline of the steps --trace-steps in FILE (Chrome trace-event JSON: Perfetto, chrome://tracing)");
  run_cmd->add_option("--trace-steps", run.trace_steps, "FROM:TO, the steps traced, counted from the run's start")
      ->capture_default_str();
  run_cmd->add_flag("--quiet", run.quiet, "no progress bar");
  run_cmd->add_flag("--no-report", run.no_report, "no report.png at the end (its figures need python3 with matplotlib)");
  const std::vector<CLI::Option*> run_settings = ishibashi::add_run_setting_flags(run_cmd, run.overrides);
  run_cmd->add_option("--dt-factor", run.dt_factor, "multiplies the time step (0.5 halves it: convergence studies)")
      ->check(ishibashi::number_in(1e-3, 1.0));
  run_cmd->add_flag("--fixed-threads", run.fixed_threads,
                    "every step on all threads (default: the team size that is fastest as the run goes)");
  run_cmd->add_option("--checkpoint-every", run.checkpoint_every_s, "write a checkpoint every this many simulated seconds")
      ->check(ishibashi::number_in(0));
  run_cmd->add_option("--checkpoint-wall", run.checkpoint_wall_s, "write a checkpoint every this many wall-clock seconds")
      ->check(ishibashi::number_in(0));
  CLI::Option* members = run_cmd->add_option("--members", run.members,
                                             "run an ensemble of N members (replacing the scenario's [ensemble] members): each "
                                             "free stone's pose drawn within the construction tolerance, outputs in "
                                             "OUT/member_NNN, probabilities in OUT/ensemble.json")
                             ->check(ishibashi::number_in(1, 100000));
  CLI::Option* probe = run_cmd->add_option("--probe", run.probe_members,
                                           "a chaos probe of N members: the run stops just before the strong motion (or at "
                                           "--branch-at); member 0 goes on from there as it is, the others with every free "
                                           "stone moved by --perturbation; how fast they part in OUT/probe.json and probe.csv")
                           ->check(ishibashi::number_in(2, 100000));
  run_cmd->add_option("--perturbation", run.perturbation_m, "the chaos probe's move of each free stone, m")
      ->check(ishibashi::number_in(1e-12, 1e-2))
      ->capture_default_str();
  run_cmd->add_option("--branch-at", run.branch_at_s,
                      "the chaos probe's branch, seconds of shaking (default: where the record's Arias intensity reaches 5 %)")
      ->check(ishibashi::number_in(0));
  probe->excludes(members);
  run_cmd->add_option("--seed", run.seed,
                      "the ensemble's seed, replacing the scenario's (member i draws from seed and i); a probe's directions")
      ->check(ishibashi::number_in(0));
  CLI::Option* member_range = run_cmd->add_option("--member-range", run.member_range,
                      "FROM:TO, run only members FROM to TO - 1 of the ensemble: a machine's share (0:4 here, 4:8 there; "
                      "copy the member_NNN folders into one folder, and a run of the whole ensemble by the same build keeps "
                      "them and writes the tables)")
      ->excludes(probe);
  run_cmd->add_option("--jobs", run.jobs,
                      "ensemble or probe members run at once (each on cores / jobs threads); under mpirun -np N an "
                      "ensemble's or a probe's members are handed out across the ranks, one per rank at a time")
      ->check(ishibashi::number_in(1, 256));
  CLI::Option* resume = run_cmd->add_option(
      "--resume", run.resume, "continue the run in this output folder from its checkpoint (bit-identical to an unbroken run)");
  resume->excludes(members);
  resume->excludes(probe);
  resume->excludes(member_range);
  resume->excludes(run_scenario_file);
  // A resumed run is the run it was: of its settings only the threads may change.
  for (CLI::Option* setting : run_settings)
    if (setting->get_name() != "--threads") resume->excludes(setting);
  for (const char* option : {"--out", "--dt-factor"}) resume->excludes(run_cmd->get_option(option));
  run_cmd->callback([&] {
    if (run.scenario.empty() && run.resume.empty()) throw CLI::RequiredError("a scenario file or --resume DIR");
  });
  return run_cmd;
}

// The `modal` command, its options read into `modal`.
CLI::App* add_modal_command(CLI::App& app, ishibashi::ModalOptions& modal) {
  CLI::App* modal_cmd = app.add_subcommand("modal", "Natural frequencies and mode shapes (modal analysis, joints held linear)");
  modal_cmd->add_option("file", modal.file, "model or scenario file")->required();
  modal_cmd->add_option("--modes", modal.modes, "number of modes")->check(ishibashi::number_in(1, 500));
  ishibashi::add_run_setting_flags(modal_cmd, modal.overrides, {"joint_rule", "subdivision", "shear_spring"});
  modal_cmd->add_option("--out", modal.out, "output folder (default: out/<name>_modal)");
  modal_cmd->add_option("--impulse", modal.impulse_s, "also run impulse responses of this many seconds (x, y, z steps)")
      ->check(ishibashi::number_in(0));
  modal_cmd->add_option("--excite", modal.excite, "one impulse: the ground step's axis")->check(CLI::IsMember({"x", "y", "z"}));
  modal_cmd->add_option("--read", modal.read, "the displacement component read (default: the step's axis)")
      ->check(CLI::IsMember({"x", "y", "z"}));
  modal_cmd->add_option("--block", modal.block, "the monitored block (default: the unit on top of the crown)")
      ->check(ishibashi::number_in(0));
  return modal_cmd;
}

// The `study` command, its options read into `study`.
CLI::App* add_study_command(CLI::App& app, ishibashi::StudyCommandOptions& study) {
  CLI::App* study_cmd = app.add_subcommand(
      "study", "A whole study: natural frequencies of its models, its seismic runs, and a report with figures");
  study_cmd->add_option("file", study.file, "study file (TOML; default: the Nishida study, scenarios/nishida_study.toml)");
  study_cmd->add_option("--out", study.out, "output folder (default: out/study, out/study_quick with --quick)");
  study_cmd->add_flag("--quick", study.quick, "the study file's short version ([quick]): what CI runs");
  study_cmd->add_option("--jobs", study.jobs, "analyses run at once (under mpirun -np N: one per rank, across the ranks)")
      ->check(ishibashi::number_in(1, 256));
  study_cmd->add_option("--threads-per-job", study.threads_per_job, "threads of each analysis (default: cores / jobs)")
      ->check(ishibashi::number_in(0, ishibashi::kMaxThreads));
  study_cmd->add_option("--members", study.members,
                         "run each seismic run as an ensemble of N members (replacing the study file's members; "
                         "0 or 1: single runs); the report gives each run's probabilities")
      ->check(ishibashi::number_in(0, 100000));
  // Every run's numerical method and joint model, as `run` takes them (a study of the
  // fast path: --damping implicit --dt 4e-5), and where its runs end (--stop-at collapse:
  // the verdicts without the debris).
  add_run_setting_flags(study_cmd, study.run_overrides,
                        {"dt_s", "damping", "solve_tolerance", "joint_rule", "shear_spring", "subdivision", "mortar_bonds",
                         "stop_at"});
  study_cmd->add_flag("--force", study.force, "rerun analyses whose outputs are current");
  study_cmd->add_flag("--no-report", study.no_report, "skip the report (needs python3 with matplotlib)");
  return study_cmd;
}

// The `sweep` command, its options read into `sweep`.
CLI::App* add_sweep_command(CLI::App& app, ishibashi::SweepCommandOptions& sweep) {
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "Every (record, intensity) run of a sweep file, then IDA and fragility curves (mpirun -np N for clusters)");
  sweep_cmd->add_option("file", sweep.file, "sweep file (TOML), e.g. scenarios/nishida_a_sweep.toml")->required();
  sweep_cmd->add_option("--out", sweep.out, "output folder (default: out/<sweep file name>)");
  sweep_cmd->add_option("--jobs", sweep.jobs, "runs at once on this machine (under mpirun: one per rank)")
      ->check(ishibashi::number_in(1, 256));
  sweep_cmd->add_option("--threads-per-job", sweep.threads_per_job, "threads of each run (default: the node's cores shared)")
      ->check(ishibashi::number_in(0, ishibashi::kMaxThreads));
  sweep_cmd->add_option("--checkpoint-wall", sweep.checkpoint_wall_s,
                        "each run's checkpoint every this many wall-clock seconds (0: none): a killed sweep's runs go on from them")
      ->check(ishibashi::number_in(0));
  return sweep_cmd;
}

// CLI11's number checks (PositiveNumber, Range) compare, and a NaN passes every comparison;
// a word failed them as "not in range 0 to 1.8e308". Every floating-point option of every
// command refuses both before its own checks run (a transform goes first).
void refuse_non_finite_numbers(CLI::App& app) {
  const CLI::Validator finite(
      [](std::string& text) {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return text + " is not a number";
        return std::isfinite(value) ? std::string() : text + " is not a finite number";
      },
      "");
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
    for (CLI::Option* option : command->get_options())
      if (option->get_type_name().rfind("FLOAT", 0) == 0) option->transform(finite);
}

}  // namespace

int main(int argc, char** argv) {
  // Line by line into a log file too, so that what goes to stdout and to stderr (progress,
  // warnings, errors) stays in the order it was said.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  CLI::App app{"ishibashi: 3-D distinct element analysis of masonry stone arch bridges"};
  app.set_version_flag("--version", std::string("ishibashi ") + ISHIBASHI_VERSION);
  app.require_subcommand(1);
  int threads = 0;
  app.add_option("--threads", threads, "OpenMP threads (default: OMP_NUM_THREADS, else every core this process may use, CPU quota included)")
      ->check(ishibashi::number_in(0, ishibashi::kMaxThreads));

  ishibashi::DemoOptions demo;
  CLI::App* demo_cmd = add_demo_command(app, demo);
  ishibashi::BuildOptions build;
  CLI::App* build_cmd = add_build_command(app, build);
  ishibashi::RunOptions run;
  CLI::App* run_cmd = add_run_command(app, run);
  ishibashi::ModalOptions modal;
  CLI::App* modal_cmd = add_modal_command(app, modal);
  ishibashi::StudyCommandOptions study;
  CLI::App* study_cmd = add_study_command(app, study);
  ishibashi::SweepCommandOptions sweep;
  CLI::App* sweep_cmd = add_sweep_command(app, sweep);

  refuse_non_finite_numbers(app);
  CLI11_PARSE(app, argc, argv);
  ishibashi::use_threads(threads);  // demo, build, modal; a run, study or sweep decides its own from it
  if (threads > 0 && !run.overrides.given.count("threads")) run.overrides.set(&ishibashi::RunSettings::threads, threads);
  if (threads > 0 && study.threads_per_job == 0) study.threads_per_job = threads;
  if (threads > 0 && sweep.threads_per_job == 0) sweep.threads_per_job = threads;
  try {
    if (*demo_cmd) return ishibashi::run_demo(demo);
    if (*build_cmd) return ishibashi::run_build(build);
    if (*run_cmd) return ishibashi::run_scenario(run);
    if (*modal_cmd) return ishibashi::run_modal(modal);
    if (*study_cmd) return ishibashi::run_study_command(study);
    if (*sweep_cmd) return ishibashi::run_sweep_command(sweep);
  } catch (const ishibashi::InputError& e) {
    std::fprintf(stderr, "ishibashi: input error: %s\n", e.what());
    return 2;
  } catch (const ishibashi::ModelError& e) {
    std::fprintf(stderr, "ishibashi: model error: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "ishibashi: out of memory: the model needs more than this machine has (fewer or larger blocks, or a "
                 "machine with more memory); the outputs written so far are complete files\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ishibashi: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
