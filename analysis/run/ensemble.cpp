#include "analysis/run/ensemble.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/batch/job_queue.h"
#include "analysis/model/fingerprint.h"
#include "analysis/run/seismic_run.h"
#include "engine/cores.h"
#include "engine/pipeline.h"
#include "io/atomic_file.h"
#include "io/input_error.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

// SplitMix64 (Steele, Lea and Flood 2014): a fully specified generator, so that a member's
// draws are the same with every compiler and library (the standard's distributions are
// not specified to the bit). One stream per (seed, member, purpose).
class DrawStream {
 public:
  DrawStream(long seed, int member, std::uint64_t purpose)
      : state_(static_cast<std::uint64_t>(seed) * 0x9E3779B97F4A7C15ull ^ (static_cast<std::uint64_t>(member) + 1) * 0xD1B54A32D192ED03ull ^
               purpose * 0xBF58476D1CE4E5B9ull) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double between(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};

constexpr std::uint64_t kMemberDraws = 1, kPoseDraws = 2;

fs::path member_folder(const fs::path& out, int member) {
  char name[32];
  std::snprintf(name, sizeof name, "member_%03d", member);
  return out / name;
}

// What a member's outputs depend on: the scenario and its files, the settings it runs with,
// the ensemble's draws and the member.
std::string member_key(const Scenario& sc, int member) {
  std::ostringstream in;
  in.precision(17);
  in << "ensemble member " << member << " of " << scenario_fingerprint(sc);
  for_each_run_setting([&](const SettingInfo& info, auto m) {
    if (std::string(info.key) != "threads") in << ' ' << info.key << '=' << setting_value(sc.settings.*m);
  });
  const EnsembleSpec& e = sc.ensemble;
  in << " seed " << e.seed << " tolerance " << e.position_tolerance_m << " friction " << e.friction_angle_deg[0] << ' '
     << e.friction_angle_deg[1] << " amplitude " << e.amplitude[0] << ' ' << e.amplitude[1];
  return inputs_key(in.str());
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// {"median", "min", "max", "count"} of the values (null where there are none).
nlohmann::ordered_json spread(const std::vector<double>& v) {
  nlohmann::ordered_json j;
  j["median"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(median(v));
  j["min"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::min_element(v.begin(), v.end()));
  j["max"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::max_element(v.begin(), v.end()));
  j["count"] = v.size();
  return j;
}

nlohmann::ordered_json probability(int hits, int trials) {
  const std::array<double, 2> ci = wilson_interval(hits, trials);
  nlohmann::ordered_json j;
  j["p"] = trials > 0 ? double(hits) / trials : 0.0;
  j["lo"] = ci[0];
  j["hi"] = ci[1];
  j["members"] = hits;
  return j;
}

// The first frame of history.csv with a fallen stone while shaking: seconds of shaking
// (-1: none).
double first_fall_s(const fs::path& history, double settle_time_s) {
  std::ifstream in(history);
  std::string line;
  if (!std::getline(in, line)) return -1;
  int time_col = -1, phase_col = -1, fallen_col = -1, col = 0;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ','); ++col) {
    if (name == "time_s") time_col = col;
    if (name == "phase") phase_col = col;
    if (name == "fallen_stones") fallen_col = col;
  }
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) f.push_back(cell);
    if (static_cast<int>(f.size()) <= std::max({time_col, phase_col, fallen_col})) continue;
    if (f[phase_col] == "shake" && std::stoi(f[fallen_col]) > 0) return std::stod(f[time_col]) - settle_time_s;
  }
  return -1;
}

}  // namespace

MemberDraw draw_member(const EnsembleSpec& spec, int member) {
  DrawStream draws(spec.seed, member, kMemberDraws);
  MemberDraw d;
  d.member = member;
  d.amplitude = draws.between(spec.amplitude[0], spec.amplitude[1]);
  const double friction = draws.between(spec.friction_angle_deg[0], spec.friction_angle_deg[1]);
  d.friction_angle_deg = spec.varies_friction() ? friction : 0.0;
  return d;
}

void perturb_model(Model& m, const EnsembleSpec& spec, const MemberDraw& draw) {
  if (draw.friction_angle_deg > 0)
    for (PairLaw& law : m.pair_law) law.tan_friction = std::tan(draw.friction_angle_deg * M_PI / 180.0);
  DrawStream draws(spec.seed, draw.member, kPoseDraws);
  const double t = spec.position_tolerance_m;
  struct Placement {
    Vec3 shift = Vec3::Zero(), axis = Vec3::UnitZ();
    double angle = 0;  // rad
  };
  std::vector<Placement> placement(m.block_count);
  std::vector<int> moved;  // the free blocks
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::free) continue;
    // Seven draws a block, whatever the tolerance: block b's depend on (seed, member, b) alone.
    const double cut = t * draws.uniform();
    Placement& p = placement[b];
    p.shift = Vec3(draws.between(-0.5, 0.5), draws.between(-0.5, 0.5), draws.between(-0.5, 0.5)) * t;
    const double z = draws.between(-1, 1), phi = 2 * M_PI * draws.uniform(), fraction = draws.uniform();
    if (t == 0) continue;  // the scenario's own blocks and poses, bit for bit
    moved.push_back(b);
    // Cut smaller: scaled about its centroid so that its nearest face moves in by `cut`. Its
    // mass, inertia and size stay as drawn (the cut is a fit, not less stone).
    double nearest = INFINITY;
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) nearest = std::min(nearest, m.face_offset_local[f]);
    const double scale = 1 - cut / nearest;
    for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) m.vertex_local[v] *= scale;
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) m.face_offset_local[f] *= scale;
    m.radius_m[b] *= scale;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    p.axis = Vec3(r * std::cos(phi), r * std::sin(phi), z);  // uniform on the sphere
    p.angle = fraction * 0.5 * t / m.radius_m[b];                // no point moves more than t / 2
  }
  if (moved.empty()) return;
  // Placed as drawn where that overlaps no neighbour more than the model itself does: a
  // block in a joint that overlaps has its shift and turn halved, round by round, and
  // dropped after kHalvings rounds (the cut alone only opens joints). The joints then close
  // under gravity while the bridge settles.
  constexpr int kHalvings = 8;
  constexpr double kFit = 1e-7;  // m: an overlap below this is a fit (the presets' joints touch to 1e-12 m)
  auto contacts_of = [&](const Model& model) {
    State s = make_initial_state(model);
    update_pose(model, s);
    update_pairs(model, s);
    update_contacts(model, s, /*first_detection=*/true, 1e-5);
    return std::move(s.contacts);
  };
  std::map<std::pair<int, int>, double> own;  // each pair's deepest overlap, cut but not moved (m, <= 0)
  {
    const SubContacts c = contacts_of(m);
    for (std::size_t i = 0; i < c.size(); ++i) {
      double& gap = own.try_emplace({c.block_a[i], c.block_b[i]}, 0.0).first->second;
      gap = std::min(gap, c.gap_m[i]);
    }
  }
  const std::vector<Vec3> position = m.initial_position;
  const std::vector<Quat> orientation = m.initial_orientation;
  std::vector<double> share(m.block_count, 1.0);
  for (int round = 0;; ++round) {
    for (int b : moved) {
      const Placement& p = placement[b];
      m.initial_position[b] = position[b] + share[b] * p.shift;
      m.initial_orientation[b] = share[b] > 0 ? (Quat(Eigen::AngleAxisd(share[b] * p.angle, p.axis)) * orientation[b]).normalized()
                                              : orientation[b];
    }
    const SubContacts c = contacts_of(m);
    std::vector<std::uint8_t> overlaps(m.block_count, 0);
    bool any = false;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const auto given = own.find({c.block_a[i], c.block_b[i]});
      if (c.gap_m[i] < (given == own.end() ? 0.0 : given->second) - kFit)
        overlaps[c.block_a[i]] = overlaps[c.block_b[i]] = 1, any = true;
    }
    bool changed = false;
    for (int b : moved)
      if (overlaps[b] && share[b] > 0) share[b] = round < kHalvings ? 0.5 * share[b] : 0.0, changed = true;
    if (!any || !changed) return;  // none left, or only between blocks where the cut left them
  }
}

std::array<double, 2> wilson_interval(int hits, int trials, double z) {
  if (trials <= 0) return {0.0, 1.0};
  const double n = trials, p = hits / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

EnsembleOutcome run_ensemble(const Scenario& scenario, const EnsembleOptions& o) {
  Scenario sc = scenario;
  if (o.members > 0) sc.ensemble.members = o.members;
  if (o.seed >= 0) sc.ensemble.seed = o.seed;
  const int n = sc.ensemble.members;
  if (n <= 0)
    throw InputError(sc.file.string() + ": an ensemble needs members: [ensemble] members = N in the scenario, or --members N");
  fs::create_directories(o.out);
  const int workers = std::max(1, std::min(o.jobs, n));
  const int threads = decide_thread_count(o.threads_per_member, workers);
  std::mutex report_lock;  // serialises on_event; outside any time step
  auto event = [&](const std::string& text) {
    const std::lock_guard<std::mutex> lock(report_lock);
    if (o.on_event) o.on_event(text);
  };
  event("ensemble of " + std::to_string(n) + " members (seed " + std::to_string(sc.ensemble.seed) + "), " +
        std::to_string(workers) + " at a time, " + std::to_string(threads) + " threads each, outputs in " + o.out.string());

  std::atomic<int> ran{0}, current{0}, failed{0}, interrupted{0};
  auto run_member = [&](int i) {
    const fs::path folder = member_folder(o.out, i);
    const std::string key = member_key(sc, i), name = "member " + std::to_string(i);
    if (outputs_current(folder, key)) {
      ++current;
      event(name + ": current, kept");
      return;
    }
    try {
      use_threads(threads);
      SeismicRunOptions options;
      options.out = folder;
      options.member = i;
      options.checkpoint_wall_s = o.checkpoint_wall_s;
      RunOverrides overrides;
      overrides.set(&RunSettings::threads, threads);
      std::unique_ptr<SeismicRun> run;
      std::string started;  // the key of the run the folder's checkpoint belongs to
      std::getline(std::ifstream(folder / "started.key"), started);
      if (started == key && fs::exists(folder / "checkpoint.bin")) {
        run = SeismicRun::resume(options, overrides);
        event(name + ": goes on from its checkpoint");
      }
      if (!run) {
        fs::remove_all(folder);  // no frames of an older run left behind
        fs::create_directories(folder);
        write_text_atomically(folder / "started.key", key + "\n");
        Scenario member = sc;
        apply_overrides(member.settings, overrides);
        run = std::make_unique<SeismicRun>(member, options);
        event(name + ": started");
      }
      const SeismicRunResult r = run->run();
      if (r.interrupted) {
        ++interrupted;
        event(name + ": interrupted (its checkpoint is kept: the ensemble goes on from it)");
        return;
      }
      fs::remove(folder / "checkpoint.bin");
      stamp_outputs(folder, key);  // last: the outputs are complete
      ++ran;
      event(name + ": done, " + std::to_string(r.fallen_stones) + " fallen stones" + (r.collapse ? ", collapse" : ""));
    } catch (const std::exception& e) {
      ++failed;
      event(name + ": FAILED: " + e.what());
    }
  };
  JobQueue queue(every_job(n));
  queue.start(workers - 1, run_member);
  queue.work(run_member);
  queue.join();

  // The tables, from every finished member's summary.json.
  EnsembleOutcome outcome;
  outcome.members = n, outcome.ran = ran, outcome.current = current, outcome.failed = failed, outcome.interrupted = interrupted;
  std::ostringstream csv;
  csv << "member,seed,amplitude,friction_angle_deg";
  for (const ResultColumn& c : result_columns()) csv << ',' << c.name;
  csv << ",first_fall_s\n";
  std::vector<double> fallen, first_opening, first_fall, crown_drop;
  for (int i = 0; i < n; ++i) {
    const fs::path folder = member_folder(o.out, i);
    if (!outputs_current(folder, member_key(sc, i))) continue;
    const nlohmann::json s = nlohmann::json::parse(std::ifstream(folder / "summary.json"));
    const MemberDraw draw = draw_member(sc.ensemble, i);
    const double fall = first_fall_s(folder / "history.csv", s["settle_time_s"].get<double>());
    csv << i << ',' << sc.ensemble.seed << ',' << draw.amplitude << ',' << draw.friction_angle_deg;
    for (const ResultColumn& c : result_columns()) {
      const nlohmann::json& v = s[c.name];
      csv << ',';
      if (v.is_boolean()) csv << (v.get<bool>() ? "yes" : "no");
      else if (v.is_string()) csv << v.get<std::string>();
      else if (!v.is_null()) csv << v.dump();
    }
    csv << ',' << (fall < 0 ? std::string() : std::to_string(fall)) << '\n';
    ++outcome.finished;
    outcome.collapses += s["collapse"].get<bool>();
    outcome.stones_fell += s["fallen_stones"].get<int>() > 0;
    outcome.ring_stones_fell += s["fallen_ring_stones"].get<int>() > 0;
    fallen.push_back(s["fallen_stones"].get<int>());
    if (!s["first_opening_s"].is_null()) first_opening.push_back(s["first_opening_s"].get<double>());
    if (fall >= 0) first_fall.push_back(fall);
    crown_drop.push_back(s["largest_crown_drop_m"].get<double>());
  }
  write_text_atomically(o.out / "ensemble.csv", csv.str());

  nlohmann::ordered_json j;
  j["scenario"] = fs::absolute(sc.file).string();
  j["members"] = n;
  j["finished"] = outcome.finished;
  j["seed"] = sc.ensemble.seed;
  j["position_tolerance_m"] = sc.ensemble.position_tolerance_m;
  j["friction_angle_deg"] = sc.ensemble.varies_friction() ? nlohmann::ordered_json(sc.ensemble.friction_angle_deg) : nullptr;
  j["amplitude"] = sc.ensemble.amplitude;
  j["interval"] = "95 % Wilson score interval of each proportion";
  j["collapse"] = probability(outcome.collapses, outcome.finished);
  j["stones_fall"] = probability(outcome.stones_fell, outcome.finished);
  j["ring_stones_fall"] = probability(outcome.ring_stones_fell, outcome.finished);
  j["fallen_stones"] = spread(fallen);
  j["first_opening_s"] = spread(first_opening);  // count: the members in which a joint opened
  j["first_fall_s"] = spread(first_fall);
  j["largest_crown_drop_m"] = spread(crown_drop);
  j["settings"] = nlohmann::ordered_json::object();
  for_each_run_setting([&](const SettingInfo& info, auto m) { j["settings"][info.key] = setting_value(sc.settings.*m); });
  write_text_atomically(o.out / "ensemble.json", j.dump(2) + "\n");
  return outcome;
}

}  // namespace ishibashi
