#include "analysis/batch/chaos_probe.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "analysis/batch/job_queue.h"
#include "analysis/batch/member_runs.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/member_draw.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "geometry/input_error.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

constexpr char kPositionsMagic[8] = {'I', 'S', 'B', 'P', 'O', 'S', '0', '1'};
struct PartingLevel {
  double separation_m;
  const char* name;  // in probe.json
};
constexpr PartingLevel kPartingLevels[] = {{1e-4, "parted_0.1_mm_s"}, {1e-3, "parted_1_mm_s"}, {1e-2, "parted_1_cm_s"}};

// What a run's outputs depend on: the scenario and its files, its settings, the branch
// point, and for a member its perturbation.
std::string probe_key(const Scenario& sc, double branch_s, const ChaosProbeOptions& o, int member) {
  std::ostringstream in;
  in.precision(17);
  in << "chaos probe of " << scenario_fingerprint(sc) << settings_key_text(sc.settings) << " branch at " << branch_s;
  if (member >= 0) in << " member " << member << " perturbation " << o.perturbation_m << " seed " << o.seed;
  return inputs_key(in.str());
}

// Moves every free stone still in the model by `distance` in a direction drawn uniformly
// on the sphere from (seed, member).
void nudge_stones(const Model& m, State& s, long seed, int member, double distance) {
  DrawStream draws(seed, member, kProbeDraws);
  for (int b = 0; b < m.block_count; ++b) {
    const double z = 2 * draws.uniform() - 1, phi = 2 * M_PI * draws.uniform();
    if (m.motion[b] != Motion::free || s.left_model[b]) continue;
    const double r = std::sqrt(1 - z * z);
    s.position[b] += distance * Vec3(r * std::cos(phi), r * std::sin(phi), z);
  }
}

// The member's folder as the branch left it: its files linked (a run replaces its files,
// never writes into them), so that the member's series continue the branch's. All but the
// checkpoint: a member's folder holds only a checkpoint of its own, written after its nudge
// (with the branch's there, a member stopped before its first checkpoint went on from it
// unperturbed, a copy of the reference: B dry's member 2, session 40).
void copy_branch(const fs::path& branch, const fs::path& folder) {
  for (const fs::directory_entry& e : fs::directory_iterator(branch)) {
    const std::string name = e.path().filename().string();
    if (name == "started.key" || name == "inputs.key" || name == "checkpoint.bin" || !e.is_regular_file()) continue;
    std::error_code linked;
    fs::create_hard_link(e.path(), folder / name, linked);
    if (linked) fs::copy_file(e.path(), folder / name, fs::copy_options::overwrite_existing);
  }
}

// The largest distance between a block's centroid in the member's row and the reference's.
double separation_m(const std::vector<double>& member, const std::vector<double>& reference) {
  double largest = 0;
  for (std::size_t i = 0; i + 2 < member.size(); i += 3) {
    const double dx = member[i] - reference[i], dy = member[i + 1] - reference[i + 1], dz = member[i + 2] - reference[i + 2];
    largest = std::max(largest, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return largest;
}

// Each perturbed member's separation from the reference at the reference's frames (NAN
// where the member has no row at that time).
std::vector<std::vector<double>> separations(const PositionSeries& reference, const std::vector<PositionSeries>& members) {
  std::vector<std::vector<double>> out;
  for (const PositionSeries& m : members) {
    std::vector<double>& sep = out.emplace_back(reference.time_s.size(), NAN);
    if (m.blocks != reference.blocks) continue;  // another model's: no separation
    std::size_t j = 0;
    for (std::size_t i = 0; i < reference.time_s.size(); ++i) {
      while (j < m.time_s.size() && m.time_s[j] < reference.time_s[i] - 1e-9) ++j;
      if (j < m.time_s.size() && std::abs(m.time_s[j] - reference.time_s[i]) <= 1e-9)
        sep[i] = separation_m(m.centroid[j], reference.centroid[i]);
    }
  }
  return out;
}

// Seconds from the first frame until the separation first reached `level`, interpolated
// in log(separation) between frames; NAN where it never did.
double parting_time_s(const std::vector<double>& time_s, const std::vector<double>& sep, double level) {
  for (std::size_t i = 0; i < sep.size(); ++i) {
    if (!(sep[i] >= level)) continue;
    if (i == 0 || !(sep[i - 1] > 0)) return time_s[i] - time_s[0];
    const double f = std::log(level / sep[i - 1]) / std::log(sep[i] / sep[i - 1]);
    return time_s[i - 1] + f * (time_s[i] - time_s[i - 1]) - time_s[0];
  }
  return NAN;
}

nlohmann::ordered_json number_or_null(double v) { return std::isnan(v) ? nlohmann::ordered_json() : nlohmann::ordered_json(v); }

// probe.csv, members.csv and probe.json from the finished members; their parting times
// and largest separation into `outcome`.
void write_probe_tables(const Scenario& sc, const ChaosProbeOptions& o, double branch_s, double settle_s,
                        ChaosProbeOutcome& outcome) {
  OutcomeTable table;
  table.draw_columns = {"perturbation_m"};
  std::vector<PositionSeries> perturbed;
  std::vector<int> perturbed_index;
  PositionSeries reference;
  for (int i = 0; i < o.members; ++i) {
    const fs::path folder = member_folder(o.out, i);
    if (!outputs_current(folder, probe_key(sc, branch_s, o, i))) continue;
    table.rows.push_back({i, folder, {i == 0 ? "0" : number_text(o.perturbation_m)}});
    if (i == 0) reference = read_positions(folder / "positions.bin");
    else perturbed.push_back(read_positions(folder / "positions.bin")), perturbed_index.push_back(i);
  }
  const std::vector<std::vector<double>> sep = separations(reference, perturbed);
  std::ostringstream csv;
  csv.precision(9);
  csv << "shaking_time_s";
  for (int i : perturbed_index) csv << ",member_" << i << "_separation_m";
  csv << '\n';
  for (std::size_t r = 0; r < reference.time_s.size(); ++r) {
    csv << reference.time_s[r] - settle_s;
    for (const std::vector<double>& s : sep) {
      csv << ',';
      if (!std::isnan(s[r])) csv << s[r];
    }
    csv << '\n';
  }
  write_text_atomically(o.out / "probe.csv", csv.str());

  nlohmann::ordered_json j;
  j["scenario"] = fs::absolute(sc.file).string();
  j["members"] = o.members;
  j["seed"] = o.seed;
  j["perturbation_m"] = o.perturbation_m;
  j["branch_shaking_s"] = branch_s;
  j["branch_rule"] = o.branch_at_s >= 0 ? "given (--branch-at)" : "where the record's Arias intensity reaches 5 %";
  outcome.parted_1cm_s.assign(std::max(0, o.members - 1), NAN);
  std::vector<std::vector<double>> parted(std::size(kPartingLevels));
  for (std::size_t k = 0; k < sep.size(); ++k) {
    nlohmann::ordered_json member;
    member["member"] = perturbed_index[k];
    double t = NAN;
    for (std::size_t l = 0; l < std::size(kPartingLevels); ++l) {
      t = parting_time_s(reference.time_s, sep[k], kPartingLevels[l].separation_m);
      member[kPartingLevels[l].name] = number_or_null(t);
      if (!std::isnan(t)) parted[l].push_back(t);
    }
    outcome.parted_1cm_s[perturbed_index[k] - 1] = t;  // the last level's
    double largest = 0;
    for (double s : sep[k]) largest = std::max(largest, std::isnan(s) ? 0.0 : s);
    member["largest_separation_m"] = largest;
    outcome.largest_separation_m = std::max(outcome.largest_separation_m, largest);
    j["parting"].push_back(member);
  }
  j["parting_time_note"] = "seconds from the branch until the separation reached the level, over the members that reached it";
  for (std::size_t l = 0; l < std::size(kPartingLevels); ++l) j[kPartingLevels[l].name] = value_spread(parted[l]);
  const OutcomeCounts counts = write_outcomes(table, o.out / "members.csv", j);
  outcome.finished = counts.finished;
  write_text_atomically(o.out / "probe.json", j.dump(2) + "\n");
}

using Event = std::function<void(const std::string&)>;

// What the probe's runs share: the scenario, the options, the branch point (seconds of
// shaking), the rank's mark for the event lines (empty on one machine) and where they go.
struct ProbeRuns {
  const Scenario& sc;
  const ChaosProbeOptions& o;
  double branch_s;
  std::string on_rank;
  Event event;
};

// The run to the branch point, in OUT/branch/, on all the node's cores (no other run of
// the probe runs while it does).
MemberStatus run_branch(const ProbeRuns& p) {
  SeismicRunOptions options;
  options.branch_at_shake_s = p.branch_s;
  options.checkpoint_wall_s = p.o.checkpoint_wall_s;
  const int threads = decide_thread_count(p.o.threads_per_member, 1);
  const fs::path branch = p.o.out / "branch";
  p.event("chaos probe: the run to its branch at " + std::to_string(p.branch_s) + " s of shaking, in " + branch.string() +
          p.on_rank);
  auto start = [&](const SeismicRunOptions& branch_options) {
    Scenario run = p.sc;
    run.settings.threads = threads;
    return std::make_unique<SeismicRun>(run, branch_options);
  };
  return run_in_folder(branch, probe_key(p.sc, p.branch_s, p.o, -1), "branch" + p.on_rank, options, threads, start, p.event);
}

// Member i from the branch's checkpoint, in OUT/member_NNN/: member 0 as the branch left
// it, each other with its stones nudged before its first step.
MemberStatus run_member(const ProbeRuns& p, int i, int threads) {
  const ChaosProbeOptions& o = p.o;
  const fs::path folder = member_folder(o.out, i), branch = o.out / "branch";
  SeismicRunOptions options;
  options.checkpoint_wall_s = o.checkpoint_wall_s;
  options.on_resume = [&](const Model& m, State& s) {
    if (i > 0) nudge_stones(m, s, o.seed, i, o.perturbation_m);
    append_positions(folder / "positions.bin", s);
  };
  options.on_frame = [&](const State& s, double) { append_positions(folder / "positions.bin", s); };
  auto start = [&](const SeismicRunOptions& member_options) {
    copy_branch(branch, folder);
    RunOverrides overrides;
    overrides.set(&RunSettings::threads, threads);
    return SeismicRun::resume(member_options, overrides, branch / "checkpoint.bin");
  };
  const std::string name = (i == 0 ? "member 0 (reference)" : "member " + std::to_string(i)) + p.on_rank;
  return run_in_folder(folder, probe_key(p.sc, p.branch_s, o, i), name, options, threads, start, p.event);
}

}  // namespace

void append_positions(const fs::path& file, const State& s) {
  const std::uint64_t blocks = s.position.size();
  const std::uintmax_t header_bytes = sizeof kPositionsMagic + sizeof blocks, row_bytes = (1 + 3 * blocks) * sizeof(double);
  std::error_code ec;
  const std::uintmax_t size = fs::exists(file) ? fs::file_size(file) : 0;
  const std::uintmax_t whole = size < header_bytes ? 0 : size - (size - header_bytes) % row_bytes;
  if (whole != size) fs::resize_file(file, whole, ec);
  if (ec) throw std::runtime_error("cannot cut " + file.string() + " back to its whole rows: " + ec.message());
  std::ofstream out(file, std::ios::binary | std::ios::app);
  if (whole == 0) {
    out.write(kPositionsMagic, sizeof kPositionsMagic);
    out.write(reinterpret_cast<const char*>(&blocks), sizeof blocks);
  }
  std::vector<double> row{s.time_s};
  for (const Vec3& x : s.position) row.insert(row.end(), {x.x(), x.y(), x.z()});
  out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
  if (!out.flush()) throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(errno));
}

PositionSeries read_positions(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[sizeof kPositionsMagic] = {};
  std::uint64_t blocks = 0;
  in.read(magic, sizeof magic).read(reinterpret_cast<char*>(&blocks), sizeof blocks);
  if (!in || std::memcmp(magic, kPositionsMagic, sizeof magic) != 0 || blocks == 0 || blocks > (1u << 26))
    throw InputError(file.string() + ": not a block-position series of this program (" + std::string(kPositionsMagic, 8) + ")");
  PositionSeries series;
  series.blocks = blocks;
  std::vector<double> row(1 + 3 * blocks);
  while (in.read(reinterpret_cast<char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)))) {
    while (!series.time_s.empty() && series.time_s.back() >= row[0]) series.time_s.pop_back(), series.centroid.pop_back();
    series.time_s.push_back(row[0]);
    series.centroid.emplace_back(row.begin() + 1, row.end());
  }
  return series;
}

ChaosProbeOutcome run_chaos_probe(const Scenario& scenario, const ChaosProbeOptions& o) {
  const Scenario& sc = scenario;
  if (o.members < 2)
    throw InputError("--probe " + std::to_string(o.members) +
                     ": a chaos probe needs 2 members or more (the reference and a perturbed run)");
  if (!(o.perturbation_m > 0))
    throw InputError("--perturbation: a chaos probe moves its stones by a distance > 0 m (1e-6: a micrometre)");
  if (sc.settings.stop_at != StopAt::end)  // its members are compared frame by frame to the end
    throw InputError(sc.file.string() + ": stop_at = \"" + setting_value(sc.settings.stop_at) +
                     "\": a chaos probe follows its members to the record's end, where they are compared; "
                     "run it with stop_at = \"end\" (--stop-at end)");
  const GroundMotion motion = prepare_ground_motion(sc.motion(), 1e-3);
  ChaosProbeOutcome outcome;
  outcome.members = o.members;
  outcome.branch_s = o.branch_at_s >= 0 ? o.branch_at_s : arias_time_s(motion, 0.05);
  if (outcome.branch_s >= motion.duration_s())
    throw InputError("--branch-at " + std::to_string(outcome.branch_s) + ": the ground motion lasts only " +
                     std::to_string(motion.duration_s()) + " s");
  fs::create_directories(o.out);
  std::mutex report_lock;  // serialises on_event; outside any time step
  const Event event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> lock(report_lock);
    if (o.on_event) o.on_event(text);
  };
  const bool ranks = o.mpi && o.mpi->size() > 1;
  const bool root = !ranks || o.mpi->rank() == 0;
  const ProbeRuns runs{sc, o, outcome.branch_s, ranks ? " (rank " + std::to_string(o.mpi->rank()) + ")" : "", event};

  // The branch: one job, on whichever rank takes it; the others wait for the members.
  MemberStatus branched = MemberStatus::failed;
  run_jobs(
      {0}, 1, o.mpi, [&](int) { return std::to_string(static_cast<int>(branched = run_branch(runs))); },
      [&](const std::string& status, int) { branched = MemberStatus(std::stoi(status)); });
  const bool go_on = branched != MemberStatus::interrupted && branched != MemberStatus::failed &&
                     fs::exists(o.out / "branch" / "checkpoint.bin");

  const int workers = ranks ? 1 : std::max(1, std::min(o.jobs, o.members));
  const int threads = decide_thread_count(o.threads_per_member, ranks ? o.mpi->ranks_on_this_node() : workers);
  std::array<std::atomic<int>, 4> counts{};  // by MemberStatus
  auto job = [&](int i) {
    const MemberStatus status = run_member(runs, i, threads);
    ++counts[static_cast<int>(status)];
    return std::to_string(static_cast<int>(status));
  };
  // Rank 0's list is the one that counts: none when the branch did not reach its point.
  run_jobs(go_on ? every_job(o.members) : std::vector<int>{}, workers, o.mpi, job,
           [&](const std::string& status, int) { ++counts[std::stoi(status)]; });
  if (!root) return outcome;
  if (!go_on) {
    outcome.interrupted = branched == MemberStatus::interrupted;
    outcome.failed = !outcome.interrupted;
    return outcome;
  }
  outcome.interrupted = counts[static_cast<int>(MemberStatus::interrupted)];
  outcome.failed = counts[static_cast<int>(MemberStatus::failed)];
  const nlohmann::json settled = nlohmann::json::parse(std::ifstream(o.out / "branch" / "summary.json"));
  write_probe_tables(sc, o, outcome.branch_s, settled["settle_time_s"].get<double>(), outcome);
  return outcome;
}

}  // namespace ishibashi
