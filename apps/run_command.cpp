#include "apps/run_command.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <tuple>
#include <utility>

#include <unistd.h>

#include "analysis/batch/chaos_probe.h"
#include "analysis/batch/ensemble.h"
#include "analysis/batch/job_queue.h"
#include "analysis/batch/study_progress.h"
#include "analysis/run/run_recorder.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "io/chrome_trace.h"
#include "geometry/input_error.h"

namespace ishibashi {
namespace {

// An energy balance that misses by more than this share of the energy exchanged is a
// fault to find, not a figure to print: the engine closes within 0.1 % at its default
// steps, and the fast path's coarse step reaches 1 % on violent impacts (scenarios/results,
// model E with mortar).
constexpr double kBalanceWarning = 0.01;

// An option's "FROM:TO" (FROM to TO - 1, 0 <= FROM < TO); `what` and `example` for its error.
std::pair<long, long> parse_range(const char* option, const std::string& text, const char* what, const char* example) {
  long from = 0, to = 0;
  char colon = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%ld %c %ld %c", &from, &colon, &to, &extra) != 3 || colon != ':' || from < 0 || to <= from)
    throw InputError(std::string(option) + " " + text + ": expected FROM:TO, two " + what +
                     " numbers with 0 <= FROM < TO (e.g. " + example + ")");
  return {from, to};
}

// Per stage: its wall time and share, and how the team's threads spent it: working
// (claiming and running chunks), waiting (at the loops' ends, or while the calling thread
// runs a serial part), and the busiest thread's work against the mean. Then the run's
// time outside the steps that recording its frames took. A resumed run's table covers the
// steps this process ran (the checkpoint's were timed by another, or not at all).
void print_profile(const SeismicRun& run, const SeismicRunResult& r) {
  const World& world = run.world();
  const Profile p = world.state().profile.since(run.profile_at_first_step());
  const long steps = r.steps - run.first_step();
  const double total = p.wall_s();
  if (steps <= 0 || total <= 0) {
    std::printf("no steps run, so no profile\n");
    return;
  }
  if (run.first_step() > 0) std::printf("the %ld steps since the checkpoint (step %ld):\n", steps, run.first_step());
  std::printf("stage                    seconds   share   work µs/step   working  waiting   serial  imbalance  stolen\n");
  for (int k = 0; k < kStageCount; ++k) {
    const StageTime& t = p.stages[k];
    if (t.wall_s == 0) continue;
    std::printf("%-23s %8.2f %6.1f %%   %12.1f  %6.1f %%  %5.1f %%  %5.1f %%  %9.2f  %4.1f %%\n", kStageNames[k], t.wall_s,
                100 * t.wall_s / total, 1e6 * t.work_s / steps, 100 * t.work_s / t.team_s, 100 * t.wait_s() / t.team_s,
                100 * t.serial_s / t.wall_s, t.imbalance(), 100 * t.stolen_share());
    if (static_cast<Stage>(k) == Stage::narrowphase_law) {  // its work by part, from the law's own clock
      std::printf("  %-21s %8s %6s     %12.1f\n", "narrowphase part", "", "", 1e6 * (t.work_s - t.law_work_s) / steps);
      std::printf("  %-21s %8s %6s     %12.1f\n", "contact law part", "", "", 1e6 * t.law_work_s / steps);
    }
  }
  std::printf("steps %ld, broadphase rebuilds %ld, contact regroups %ld, %.1f steps/s, mean team %.2f of %d threads\n", steps,
              p.broadphase_rebuilds, p.contact_regroups, steps / total, double(p.thread_steps) / steps,
              world.thread_tuner().max_threads());
  std::printf("  work: thread-seconds claiming and running the stage's chunks, and its serial parts (growing with the\n"
              "  threads: they slow each other through memory); waiting: the rest of the team's time in the stage; serial:\n"
              "  share of the stage one thread runs alone; imbalance: the busiest thread's chunks against the mean;\n"
              "  stolen: chunks a thread took from another's range, whose data lay in another core's cache; each chunk of\n"
              "  pairs runs its contact law in the narrowphase's pass, and its parts' work is split by the law's own clock\n");
  std::printf("frames: %.1f s of the run's %.1f s wall (%.1f %%) recording the counts, ParaView files and history.csv "
              "(--output-interval sets how often)\n", r.output_wall_s, r.wall_s, 100 * r.output_wall_s / r.wall_s);
  if (world.model().options.damping == Damping::implicit)
    std::printf("implicit dashpots: %.2f conjugate-gradient iterations per step (tolerance %g), %ld steps stopped unconverged\n",
                double(p.damping_iterations) / steps, world.model().options.damping_solve_tolerance, p.damping_unconverged);
}

// A line per member's event on stdout, unless --quiet.
std::function<void(const std::string&)> event_printer(const RunOptions& o) {
  return [quiet = o.quiet](const std::string& text) {
    if (!quiet) std::printf("%s\n", text.c_str()), std::fflush(stdout);
  };
}

}  // namespace

// An ensemble of the scenario (ensemble.h): its members, then the probabilities.
int run_ensemble_of(const RunOptions& o, Scenario sc) {
  const MpiSession mpi;  // under mpirun: the members handed out across the ranks
  EnsembleOptions options;
  options.mpi = &mpi;
  options.out = o.out.empty() ? std::filesystem::path("out") / o.scenario.stem() : o.out;
  options.members = o.members;
  options.seed = o.seed;
  options.jobs = o.jobs;
  if (!o.member_range.empty()) {
    const auto [from, to] = parse_range("--member-range", o.member_range, "member", "0:4 runs members 0 to 3");
    options.first_member = static_cast<int>(from);
    options.end_member = static_cast<int>(std::min<long>(to, INT_MAX));
  }
  options.threads_per_member = sc.settings.threads;
  if (o.checkpoint_wall_s > 0) options.checkpoint_wall_s = o.checkpoint_wall_s;
  options.on_event = event_printer(o);
  options.member_reports = !o.no_report;
  options.report_title = sc.model.name + ", " + o.scenario.filename().string();
  stop_runs_on_interrupt();
  const EnsembleOutcome r = run_ensemble(sc, options);
  if (mpi.rank() != 0) return r.interrupted > 0 ? 130 : r.failed > 0 ? 1 : 0;
  std::printf("ensemble: %d members, %d ran, %d were current, %d interrupted, %d failed\n", r.members, r.ran, r.current,
              r.interrupted, r.failed);
  auto share = [&](int hits) {
    const std::array<double, 2> ci = wilson_interval(hits, r.finished);
    char text[96];
    std::snprintf(text, sizeof text, "%d of %d (95 %% interval %.2f-%.2f)", hits, r.finished, ci[0], ci[1]);
    return std::string(text);
  };
  std::printf("  collapse: %s\n  any stone fell: %s\n  a ring stone fell: %s\n", share(r.collapses).c_str(),
              share(r.stones_fell).c_str(), share(r.ring_stones_fell).c_str());
  std::string modes;  // how_it_fails.h, failure_mode_of
  for (const auto& [mode, members] : r.failure_modes) modes += (modes.empty() ? "" : "; ") + mode + ": " + share(members);
  if (!modes.empty()) std::printf("  how they fail: %s\n", modes.c_str());
  if (sc.settings.stop_at == StopAt::collapse)
    std::printf("  (stop_at = \"collapse\": each collapsing member ended at its collapse, so its fallen stones and crown drop "
                "are those at that frame, and a ring stone that would have fallen later is not counted)\n");
  const std::string not_drawn = o.no_report || r.finished == 0
                                    ? ""
                                    : run_report_script("ensemble_figure.py", options.out,
                                                        sc.model.name + ", " + o.scenario.filename().string());
  std::printf("outputs in %s: member_NNN/ (each member's run%s), ensemble.csv, ensemble.json%s\n", options.out.c_str(),
              o.no_report ? "" : " and its report.png",
              o.no_report || r.finished == 0 || !not_drawn.empty() ? "" : ", ensemble.png (every member through the shaking)");
  if (!not_drawn.empty()) std::printf("warning: ensemble.png not drawn: %s\n", not_drawn.c_str());
  return r.interrupted > 0 ? 130 : r.failed > 0 ? 1 : 0;
}

// A chaos probe of the scenario (chaos_probe.h): how fast runs part that differ by far
// less than any tolerance.
int run_probe_of(const RunOptions& o, const Scenario& sc) {
  const MpiSession mpi;  // under mpirun: the branch on one rank, then the members across the ranks
  ChaosProbeOptions options;
  options.mpi = &mpi;
  options.out = o.out.empty() ? std::filesystem::path("out") / (o.scenario.stem().string() + "_probe") : o.out;
  options.members = o.probe_members;
  options.seed = o.seed >= 0 ? o.seed : 1;
  options.perturbation_m = o.perturbation_m;
  options.branch_at_s = o.branch_at_s;
  options.jobs = o.jobs;
  options.threads_per_member = sc.settings.threads;
  if (o.checkpoint_wall_s > 0) options.checkpoint_wall_s = o.checkpoint_wall_s;
  options.on_event = event_printer(o);
  stop_runs_on_interrupt();
  const ChaosProbeOutcome r = run_chaos_probe(sc, options);
  if (mpi.rank() != 0) return 0;  // rank 0 reports
  std::printf("chaos probe: %d members branched at %.3f s of shaking, %d finished, %d interrupted, %d failed\n", r.members,
              r.branch_s, r.finished, r.interrupted, r.failed);
  for (std::size_t k = 0; k < r.parted_1cm_s.size(); ++k)
    std::printf("  member %zu: %s\n", k + 1,
                std::isnan(r.parted_1cm_s[k]) ? "did not part from the reference by 1 cm"
                                               : ("parted from the reference by 1 cm " + std::to_string(r.parted_1cm_s[k]) +
                                                  " s after the branch").c_str());
  std::printf("largest separation %.3g m; outputs in %s: branch/, member_NNN/, probe.csv, probe.json, members.csv\n",
              r.largest_separation_m, options.out.c_str());
  return r.interrupted > 0 ? 130 : r.failed > 0 ? 1 : 0;
}

// The shaking's peaks by component, and the whole records' checked: the first check of a
// record's units (a record in gal read as g shakes at hundreds of g).
void print_ground_motion_peaks(const Scenario& sc, const GroundMotionPeaks& p) {
  const Vec3 a = p.accel_m_s2, v = p.velocity_m_s, d = p.displacement_m;
  std::printf("  peak ground acceleration x %.3g, y %.3g, z %.3g m/s^2 (%.3g, %.3g, %.3g g), velocity %.3g, %.3g, %.3g m/s, "
              "displacement %.3g, %.3g, %.3g m\n", a.x(), a.y(), a.z(), a.x() / kStandardGravity_m_s2, a.y() / kStandardGravity_m_s2,
              a.z() / kStandardGravity_m_s2, v.x(), v.y(), v.z(), d.x(), d.y(), d.z());
  constexpr double kLargest_g = 5, kSmallest_g = 1e-3;  // recorded peaks reach about 4 g
  GroundMotionSpec whole = sc.ground_motion;  // a window may hold only the quiet start
  whole.start_s = whole.duration_s = 0;
  const double largest_g = ground_motion_peaks(whole).accel_m_s2.maxCoeff() / kStandardGravity_m_s2;
  if (largest_g > kLargest_g || (largest_g > 0 && largest_g < kSmallest_g))
    std::printf("warning: the records' peak ground acceleration of %.3g g %s: check each record's unit in %s ([ground_motion] unit = "
                "\"g\", \"gal\" or \"m/s2\" for columns; an .AT2 file says its own) and its scale\n",
                largest_g, largest_g > kLargest_g ? "is above any earthquake recorded (about 4 g)" : "would move no masonry",
                sc.file.c_str());
}

int run_scenario(const RunOptions& o) {
  Scenario scenario;
  if (o.resume.empty()) {
    scenario = read_scenario(o.scenario);
    apply_overrides(scenario.settings, o.overrides);
    if (o.members > 0 || (o.probe_members <= 0 && scenario.ensemble.members > 0))
      return run_ensemble_of(o, std::move(scenario));
    if (!o.member_range.empty())
      throw InputError("--member-range " + o.member_range + ": a share of an ensemble, but " + o.scenario.string() +
                       " has no [ensemble] table and no --members was given");
  }
  if (!o.resume.empty() && !std::filesystem::exists(o.resume / "checkpoint.bin") &&
      std::filesystem::exists(o.resume / "member_000"))
    throw InputError(o.resume.string() + ": the folder of an ensemble or a chaos probe, whose members resume each from its " +
                     "own checkpoint: give the command that made it again (its scenario, --members N or --probe N, and --out " +
                     o.resume.string() + "); finished members are kept");
  if (const double shaken_s = o.resume.empty() ? -1 : finished_shaking_s(o.resume); shaken_s >= 0) {
    // Its last checkpoint lies before the end: going on from it would only write the end again.
    std::printf("%s: the run there finished (%.2f s of shaking, summary.json): nothing to resume; to run it again, run "
                "its scenario with --out %s\n", o.resume.c_str(), shaken_s, o.resume.c_str());
    return 0;
  }
  if (o.probe_members > 0) return run_probe_of(o, scenario);
  if (const MpiSession mpi; mpi.size() > 1)  // every rank would write the same folder
    throw InputError("run under mpirun with " + std::to_string(mpi.size()) +
                     " ranks: only an ensemble's or a chaos probe's members (--members N, --probe N) are handed out "
                     "across ranks; run a single run without mpirun (or with -np 1)");
  SeismicRunOptions options;
  options.out = !o.resume.empty() ? o.resume : o.out.empty() ? std::filesystem::path("out") / o.scenario.stem() : o.out;
  options.dt_factor = o.dt_factor;
  options.adaptive_threads = !o.fixed_threads;
  options.checkpoint_every_s = o.checkpoint_every_s;
  options.checkpoint_wall_s = o.checkpoint_wall_s;
  options.time_threads = o.profile;
  if (!o.trace.empty()) std::tie(options.trace_first_step, options.trace_last_step) = parse_range("--trace-steps", o.trace_steps, "step", "1000:1100");
  options.on_warning = [](const std::string& text) { std::fprintf(stderr, "\n  warning: %s\n", text.c_str()); };
  const auto shake0 = std::chrono::steady_clock::now();
  // A bar on a terminal; into a log file (nohup, a cluster's job) a line every tenth of the
  // shaking, where the bar's redraws made one line of hundreds.
  const bool bar = !o.quiet && isatty(STDERR_FILENO);
  bool settle_shown = false;  // on a terminal: the settling's line, ended by the shaking's bar
  const auto print_line = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  if (bar) {
    options.on_settle_frame = [&](const State& s, double settle_max_s, double settled_below_j) {
      settle_shown = true;
      std::fprintf(stderr, "\r  settling: %.2f s of at most %.2f s, kinetic energy %.3g J (settled below %.3g J)   ", s.time_s,
                   settle_max_s, s.energy.kinetic_j, settled_below_j);
    };
    options.on_frame = [&](const State&, double done) {
      if (settle_shown) std::fprintf(stderr, "\n"), settle_shown = false;
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - shake0).count();
      std::fprintf(stderr, "\r  shaking [%-30s] %5.1f%%  about %s to go   ", std::string(static_cast<int>(30 * done), '#').c_str(),
                   100 * done, duration_text(elapsed * (1 - done) / done).c_str());
    };
  } else if (!o.quiet) {
    options.on_settle_frame = settling_lines("  run", print_line);
    options.on_frame = with_progress_lines(nullptr, "  run", print_line);
  }
  const std::unique_ptr<SeismicRun> made = !o.resume.empty()
                                               ? SeismicRun::resume(options, o.overrides)  // threads: the only setting a resume may change
                                               : std::make_unique<SeismicRun>(scenario, options);
  SeismicRun& run = *made;
  const Scenario& sc = run.scenario();
  const Model& m = run.world().model();
  if (!o.resume.empty()) std::printf("resuming %s from its checkpoint\n", options.out.c_str());
  std::printf("%s: %d blocks, %d sub-contacts (%s joint rule), dt = %.3g s, at most %d threads; ground motion %.2f s (from "
              "%.2f s of the record)\n", sc.model.name.c_str(), m.block_count, sub_contact_count(run.world().state()),
              joint_rule_name(sc.settings.joint_rule), run.dt_s(), run.world().thread_tuner().max_threads(),
              run.ground_motion().duration_s(), sc.settings.start_s);
  print_ground_motion_peaks(sc, run.ground_motion_peaks());
  if (const int cores = usable_cores(); run.world().thread_tuner().max_threads() > cores)
    std::printf("warning: %d threads on %d usable cores (affinity and CPU quota): the threads beyond the cores wait for "
                "their turn at every step (--threads 0 takes every usable core)\n", run.world().thread_tuner().max_threads(), cores);
  if (sc.model.bridge.mortar_pa > 0)
    std::printf("  mortar %s, %s\n", mortar_description(sc.model.bridge).c_str(),
                sc.settings.mortar_bonds == MortarBonds::settled ? "set once the bridge has settled" : "set from the first step");
  if (!m.ties.empty()) std::printf("  %s\n", ties_description(sc.model).c_str());
  if (sc.settings.duration_s > run.ground_motion().duration_s() + run.dt_s())
    std::printf("  the record ends %.2f s after start_s: the run shakes for that long, not the %.2f s asked\n",
                run.ground_motion().duration_s(), sc.settings.duration_s);
  std::printf("  stability limit %.3g s, set by %s and its joints%s\n", run.stability_limit_s(),
              m.block_label(run.limiting_block()).c_str(),
              sc.settings.damping == Damping::capped     ? " (springs alone: dashpots capped where dt would not resolve them)"
              : sc.settings.damping == Damping::implicit ? " (springs alone: dashpots implicit)"
                                                : "");
  if (sc.settings.damping == Damping::capped) {
    const std::vector<double>& scale = run.world().state().damping_scale;
    const long capped = std::count_if(scale.begin(), scale.end(), [](double f) { return f < 1; });
    std::printf("  dashpots capped on %ld blocks (smallest factor %.3f)\n", capped, *std::min_element(scale.begin(), scale.end()));
  }
  stop_runs_on_interrupt();
  const SeismicRunResult r = run.run();
  if (bar) std::fprintf(stderr, "\n");

  char when[96] = "interrupted while settling";
  if (!r.interrupted || r.shaking_time_s > 0)
    std::snprintf(when, sizeof when, "%s after %.2f s of shaking",
                  r.interrupted     ? "interrupted"
                  : r.stopped_early ? "collapse, stopped there (--stop-at collapse),"  // the only stop a plain run has
                                    : "done",
                  r.shaking_time_s);
  char crown[64] = "no crown unit monitored";  // an imported model has none unless [monitor] names one
  if (run.monitored_block() >= 0) std::snprintf(crown, sizeof crown, "largest crown drop %.4f m", r.largest_crown_drop_m);
  std::printf("%s: %d fallen stones, %d of %d joints cracked (%d open now), largest slip %.4f m, %s, first opening %s\n",
              when, r.fallen_stones, r.joint_counts.cracked, r.joints, r.joint_counts.open, r.joint_counts.largest_slip_m,
              crown, r.first_opening_s < 0 ? "none" : (std::to_string(r.first_opening_s) + " s").c_str());
  // A bridge that stands with its ring hinged came near a mechanism: say where, as for a collapse.
  if (r.fallen_stones > 0 || r.most_ring_hinges > 0) std::printf("how it fails: %s\n", how_it_fails_of(options.out).c_str());
  std::printf("energy balance error %.3g %% of the energy exchanged; re-clipped contacts made %.3g %%\n",
              100 * r.balance_error_relative, 100 * r.reclip_relative);
  if (std::abs(r.balance_error_relative) > kBalanceWarning)
    std::printf("warning: the energy balance misses by more than %.0f %%: a step too coarse for this run's impacts (try "
                "--dt-factor 0.5 and compare), or a fault worth reporting\n", 100 * kBalanceWarning);
  if (std::abs(r.reclip_relative) > kBalanceWarning)  // first order in dt (Energy::reclip_j)
    std::printf("warning: contacts re-clipped during impacts made more than %.0f %% of the energy exchanged: a step too "
                "coarse for this run's impacts (try --dt-factor 0.5 and compare)\n", 100 * kBalanceWarning);
  if (const long unconverged = run.world().state().profile.damping_unconverged; unconverged > 0)
    std::printf("warning: in %ld steps the implicit dashpots' solve stopped at its iteration limit before its tolerance; "
                "a smaller dt (--dt) makes it converge\n", unconverged);
  if (o.profile) print_profile(run, r);
  if (!o.trace.empty()) {
    const StageTrace& trace = run.world().trace();
    write_chrome_trace(trace, sc.model.name + " (" + sc.file.filename().string() + ")", o.trace);
    const long traced = std::count_if(trace.slices.begin(), trace.slices.end(), [](const TraceSlice& t) { return t.stage < 0; });
    std::printf("trace of %ld steps (%ld:%ld asked) in %s: open it in https://ui.perfetto.dev or chrome://tracing\n", traced,
                trace.first_step, trace.last_step, o.trace.c_str());
  }
  const std::string not_drawn =
      o.no_report ? "" : run_report_script("run_report.py", options.out, sc.model.name + ", " + sc.file.filename().string());
  std::printf("outputs in %s: blocks.pvd, contacts.pvd, %sview.pvsm (ParaView: File > Load State, files searched in its "
              "folder), history.csv, summary.json%s\n", options.out.c_str(), m.ties.empty() ? "" : "ties.pvd (the tie rods), ",
              o.no_report || !not_drawn.empty() ? "" : ", report.png (the run at a glance)");
  if (!not_drawn.empty()) std::printf("warning: report.png not drawn: %s\n", not_drawn.c_str());
  return r.interrupted ? 130 : 0;
}

}  // namespace ishibashi
