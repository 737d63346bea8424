#include "analysis/sweep.h"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "analysis/fingerprint.h"
#include "analysis/seismic_run.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/scenario_file.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;
constexpr double kG = 9.80665;
// Which run, whether it failed, the run's result (run_result.h) and where it ran: wall_s and
// host, which differ from machine to machine, last.
const std::string kHeader = "scenario,record,level,scale_factor,pga_g,failed," + result_csv_header() + ",host\n";

// Index of a column of kHeader.
std::size_t column(const std::string& name) {
  std::stringstream header(kHeader.substr(0, kHeader.size() - 1));
  std::size_t index = 0;
  for (std::string f; std::getline(header, f, ','); ++index)
    if (f == name) return index;
  throw std::logic_error("sweep.csv has no column " + name);
}
constexpr int kRowTag = 1, kCaseTag = 2;  // worker -> rank 0: a finished row; rank 0 -> worker: the next case

struct Case {
  int scenario, record, level;
  std::string key;  // "scenario,record,level": the first three fields of its row
};

std::string scenario_name(const SweepFile& sweep, int scenario) { return sweep.scenarios[scenario].stem().string(); }

std::string level_label(double level) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", level);
  return text;
}

std::string host_name() {
  char name[256] = "";
  gethostname(name, sizeof name - 1);
  return name;
}

// One run of the sweep; returns its row (with the newline).
std::string run_case(const SweepFile& sweep, const Case& c, int threads, const fs::path& out) {
  const SweepRecord& record = sweep.records[c.record];
  const double level = sweep.levels[c.level];
  Scenario sc = read_scenario(sweep.scenarios[c.scenario]);
  if (sweep.duration_s >= 0) sc.duration_s = sweep.duration_s;
  GroundMotionSpec motion = record.motion;
  motion.duration_s = sc.duration_s;
  motion.baseline_correction = sc.ground_motion.baseline_correction;
  const double record_pga_g = horizontal_pga_m_s2(motion) / kG;
  if (sweep.scale_to_pga && !(record_pga_g > 0))
    throw InputError(sweep.file.string() + ": record '" + record.name + "' has no horizontal acceleration to scale to a PGA");
  const double factor = sweep.scale_to_pga ? level / record_pga_g : level;
  for (auto& component : motion.component)
    if (component) component->scale *= factor;
  sc.ground_motion = motion;
  sc.threads = threads;

  SeismicRunOptions options;
  options.out = out / "runs" / scenario_name(sweep, c.scenario) / (record.name + "_" + level_label(level));
  fs::remove_all(options.out);  // a run that died half-way starts again
  SeismicRun run(sc, options);
  const SeismicRunResult r = run.run();
  if (r.interrupted) throw std::runtime_error("interrupted");
  const FailureCriteria& f = sweep.failure;
  const bool failed = (f.collapse && r.collapse) || (f.crown_drop_m >= 0 && r.largest_crown_drop_m > f.crown_drop_m) ||
                      (f.fallen_stones >= 0 && r.fallen_stones >= f.fallen_stones);
  std::ostringstream row;
  row.precision(9);
  row << c.key << "," << factor << "," << record_pga_g * factor << "," << (failed ? 1 : 0) << "," << result_csv_values(r) << ","
      << host_name() << "\n";
  return row.str();
}

// The complete rows of sweep.csv (a row cut short by a crash is dropped).
std::vector<std::string> finished_rows(const fs::path& file) {
  std::vector<std::string> rows;
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  std::size_t at = text.find('\n');  // past the header
  while (at != std::string::npos && at + 1 < text.size()) {
    const std::size_t end = text.find('\n', at + 1);
    if (end == std::string::npos) break;
    rows.push_back(text.substr(at + 1, end - at));
    at = end;
  }
  return rows;
}

std::vector<std::string> fields(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row.substr(0, row.find('\n')));
  for (std::string f; std::getline(s, f, ',');) out.push_back(f);
  return out;
}

// One scenario's outcomes: (PGA, failed) of each run, in the order of the rows.
struct Outcomes {
  std::vector<double> pga;
  std::vector<int> failed;
  std::map<std::string, int> by_case;  // "record,level" -> failed
};

// The IDA curves, a fragility fit per scenario, and each scenario against the first.
std::vector<ScenarioFragility> write_curves(const SweepFile& sweep, const fs::path& out, const std::vector<std::string>& rows) {
  std::map<std::string, std::vector<std::pair<double, double>>> ida;  // "scenario,record" -> (PGA, crown drop)
  std::map<std::string, Outcomes> outcomes;
  for (const std::string& row : rows) {
    const std::vector<std::string> f = fields(row);
    if (f.size() <= column("host")) continue;
    const std::string& scenario = f[column("scenario")];
    const double pga_g = std::stod(f[column("pga_g")]);
    const int failed = std::stoi(f[column("failed")]);
    ida[scenario + "," + f[column("record")]].push_back({pga_g, std::stod(f[column("largest_crown_drop_m")])});
    Outcomes& o = outcomes[scenario];
    o.pga.push_back(pga_g);
    o.failed.push_back(failed);
    o.by_case[f[column("record")] + "," + f[column("level")]] = failed;
  }
  std::ostringstream curves;
  curves.precision(9);
  curves << "scenario,record,pga_g,crown_drop_m\n";
  for (auto& [key, points] : ida) {
    std::sort(points.begin(), points.end());
    for (const auto& [x, drop] : points) curves << key << "," << x << "," << drop << "\n";
  }
  write_text_atomically(out / "ida.csv", curves.str());

  double highest_pga = 0;  // the curves reach 1.5 times the highest PGA run
  for (const auto& [name, o] : outcomes)
    for (double x : o.pga) highest_pga = std::max(highest_pga, x);
  const double top = highest_pga > 0 ? 1.5 * highest_pga : 1.0;
  std::ostringstream fits, curve, comparison;
  fits.precision(9);
  comparison.precision(9);
  fits << "scenario,median_g,beta,degenerate,outcomes,failures,log_likelihood\n";
  curve << "scenario,pga_g,failure_probability\n";
  comparison << "scenario,reference,cases,both_stand,both_fail,only_reference_fails,only_scenario_fails,"
                "likelihood_ratio,p_same_fragility\n";
  std::vector<ScenarioFragility> result;
  const Outcomes none;
  for (int k = 0; k < static_cast<int>(sweep.scenarios.size()); ++k) {
    ScenarioFragility r;
    r.scenario = scenario_name(sweep, k);
    const auto found = outcomes.find(r.scenario);
    const Outcomes& o = found == outcomes.end() ? none : found->second;
    r.fit = fit_lognormal_fragility(o.pga, o.failed);
    const FragilityFit& fit = r.fit;
    fits << r.scenario << "," << fit.median << "," << fit.beta << "," << (fit.degenerate ? 1 : 0) << "," << fit.outcomes
         << "," << fit.failures << "," << fit.log_likelihood << "\n";
    for (int i = 1; i <= 150; ++i) curve << r.scenario << "," << top * i / 150 << "," << failure_probability(fit, top * i / 150) << "\n";
    if (k > 0) {  // against the reference, case by case (same record and level) and as curves
      r.reference = result.front().scenario;
      const auto ref_found = outcomes.find(r.reference);
      const Outcomes& ref = ref_found == outcomes.end() ? none : ref_found->second;
      for (const auto& [key, failed] : o.by_case) {
        const auto other = ref.by_case.find(key);
        if (other == ref.by_case.end()) continue;
        ++r.cases;
        r.both_fail += failed && other->second;
        r.both_stand += !failed && !other->second;
        r.only_reference_fails += !failed && other->second;
        r.only_scenario_fails += failed && !other->second;
      }
      r.against_reference = compare_fragilities(ref.pga, ref.failed, o.pga, o.failed);
      comparison << r.scenario << "," << r.reference << "," << r.cases << "," << r.both_stand << "," << r.both_fail << ","
                 << r.only_reference_fails << "," << r.only_scenario_fails << "," << r.against_reference.statistic << ","
                 << r.against_reference.p_value << "\n";
    }
    result.push_back(r);
  }
  write_text_atomically(out / "fragility_fit.csv", fits.str());
  write_text_atomically(out / "fragility.csv", curve.str());
  if (sweep.scenarios.size() > 1) write_text_atomically(out / "comparison.csv", comparison.str());
  return result;
}

}  // namespace

MpiSession::MpiSession() {
  active_ = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_RANK") || std::getenv("PMIX_RANK");
  if (!active_) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);  // MPI only on the main thread
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &local_size_);
  MPI_Comm_free(&node);
}

MpiSession::~MpiSession() {
  if (active_) MPI_Finalize();
}

namespace {

// A worker rank: asks rank 0 for a case, runs it, sends its row with the next request.
SweepOutcome serve_rank_zero(const SweepFile& sweep, const std::vector<Case>& cases, int threads, const fs::path& out) {
  SweepOutcome outcome;
  std::string message;
  for (;;) {
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kRowTag, MPI_COMM_WORLD);
    int next = -1;
    MPI_Recv(&next, 1, MPI_INT, 0, kCaseTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (next < 0) break;
    try {
      message = run_case(sweep, cases[next], threads, out);
      ++outcome.ran;
    } catch (const std::exception& e) {
      message = "!" + cases[next].key + ": " + e.what();
      ++outcome.failed;
    }
  }
  return outcome;
}

// The cases not yet in sweep.csv (a sweep resumes where it stopped); rewrites the table
// without a row a crash cut short. A table of other columns (another version's) is refused
// rather than mixed with this one's rows.
std::vector<int> cases_to_run(const fs::path& table, const std::vector<Case>& cases) {
  std::string header;
  std::getline(std::ifstream(table), header);
  if (!header.empty() && header + "\n" != kHeader)
    throw InputError(table.string() + ": its columns are not this version's (\"" + header.substr(0, 40) +
                     "...\"); move it away, or give the sweep another --out");
  std::vector<std::string> rows = finished_rows(table);
  std::set<std::string> done;
  for (const std::string& row : rows) {
    const std::vector<std::string> f = fields(row);
    if (f.size() >= 3) done.insert(f[0] + "," + f[1] + "," + f[2]);
  }
  std::string kept = kHeader;
  for (const std::string& row : rows) kept += row;
  write_text_atomically(table, kept);
  std::vector<int> pending;
  for (int i = 0; i < static_cast<int>(cases.size()); ++i)
    if (!done.count(cases[i].key)) pending.push_back(i);
  return pending;
}

}  // namespace

// Rank 0's queue serves its own worker threads and the other ranks' requests in one
// function: both share the lock, the open table and the counts.
SweepOutcome run_sweep(const SweepFile& sweep, const SweepOptions& o, const MpiSession& mpi) {
  const bool root = mpi.rank() == 0;
  auto event = [&](const std::string& text) {
    if (o.on_event) o.on_event(text);
  };
  // The variants of one (record, level) next to each other: a sweep stopped part way has
  // compared what it has run.
  std::vector<Case> cases;
  for (int r = 0; r < static_cast<int>(sweep.records.size()); ++r)
    for (int l = 0; l < static_cast<int>(sweep.levels.size()); ++l)
      for (int k = 0; k < static_cast<int>(sweep.scenarios.size()); ++k)
        cases.push_back({k, r, l, scenario_name(sweep, k) + "," + sweep.records[r].name + "," + level_label(sweep.levels[l])});
  const int runs_here = mpi.size() > 1 ? 1 : std::max(1, o.jobs);
  const int node_share = mpi.size() > 1 ? mpi.ranks_on_this_node() : runs_here;
  const int threads = decide_thread_count(o.threads_per_job, node_share);
  SweepOutcome outcome;

  if (!root) return serve_rank_zero(sweep, cases, threads, o.out);

  // ---- rank 0 (or the only process): the queue, sweep.csv and the curves ----
  fs::create_directories(o.out);
  const fs::path table = o.out / "sweep.csv";
  const std::vector<int> pending = cases_to_run(table, cases);
  outcome.kept = static_cast<int>(cases.size() - pending.size());
  event("sweep: " + std::to_string(cases.size()) + " runs (" + std::to_string(sweep.scenarios.size()) + " scenarios x " +
        std::to_string(sweep.records.size()) + " records x " +
        std::to_string(sweep.levels.size()) + " levels), " + std::to_string(outcome.kept) + " done before; " +
        std::to_string(mpi.size() > 1 ? mpi.size() : runs_here) + (mpi.size() > 1 ? " MPI ranks" : " at a time") + ", " +
        std::to_string(threads) + " threads each");

  std::mutex lock;  // the queue, sweep.csv and the counts; outside any time step
  std::size_t next_pending = 0;
  std::ofstream append(table, std::ios::app);
  auto take = [&]() -> int {
    const std::lock_guard<std::mutex> guard(lock);
    return next_pending < pending.size() && !stop_requested() ? pending[next_pending++] : -1;
  };
  auto finish = [&](const std::string& message, int rank) {
    const std::lock_guard<std::mutex> guard(lock);
    if (message.empty()) return;
    if (message[0] == '!') {
      ++outcome.failed;
      event("FAILED " + message.substr(1) + " (rank " + std::to_string(rank) + ")");
      return;
    }
    append << message << std::flush;  // one complete row at a time
    ++outcome.ran;
    event(message.substr(0, message.find(',', message.find(',', message.find(',') + 1) + 1)) + ": done (rank " +
          std::to_string(rank) + ")");
  };
  auto local_worker = [&] {
    for (int i = take(); i >= 0; i = take()) {
      event(cases[i].key + ": started");
      try {
        finish(run_case(sweep, cases[i], threads, o.out), 0);
      } catch (const std::exception& e) {
        finish("!" + cases[i].key + ": " + e.what(), 0);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int w = 0; w < runs_here; ++w) pool.emplace_back(local_worker);
  // The other ranks' requests, on this (the main) thread; it polls, so that it does not
  // take a core from this rank's own run.
  for (int remote = mpi.size() - 1; remote > 0;) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kRowTag, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    std::string message(static_cast<std::size_t>(length), '\0');
    MPI_Recv(message.data(), length, MPI_CHAR, status.MPI_SOURCE, kRowTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    finish(message, status.MPI_SOURCE);
    const int next = take();
    if (next >= 0) event(cases[next].key + ": started on rank " + std::to_string(status.MPI_SOURCE));
    MPI_Send(&next, 1, MPI_INT, status.MPI_SOURCE, kCaseTag, MPI_COMM_WORLD);
    if (next < 0) --remote;
  }
  for (std::thread& t : pool) t.join();
  append.close();

  outcome.fragility = write_curves(sweep, o.out, finished_rows(table));
  if (!stop_requested()) {
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string command = python + " " + ISHIBASHI_SOURCE_DIR "/analysis/sweep_plots.py \"" + o.out.string() + "\"";
    outcome.plots_written = std::system(command.c_str()) == 0;
  }
  return outcome;
}

}  // namespace ishibashi
