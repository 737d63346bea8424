#include "analysis/batch/member_runs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "analysis/batch/job_queue.h"
#include "analysis/batch/study_progress.h"
#include "engine/cores.h"
#include "io/atomic_file.h"
#include "io/vtk_output.h"

namespace ishibashi {
namespace fs = std::filesystem;
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
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

// In how many members each stone fell (summary.json's fallen_blocks; a member written
// before that list was, is left out and not counted).
struct FallMap {
  int members = 0;
  std::vector<int> falls;  // by block id
  fs::path first_frame;    // a member's first blocks frame: the model's blocks, to colour

  void add(const nlohmann::json& summary, const fs::path& folder) {
    if (!summary.contains("fallen_blocks")) return;
    ++members;
    for (int b : summary["fallen_blocks"]) {
      if (b >= static_cast<int>(falls.size())) falls.resize(b + 1, 0);
      ++falls[b];
    }
    if (first_frame.empty() && fs::exists(folder / "blocks_000000.vtu")) first_frame = folder / "blocks_000000.vtu";
  }
  // {"members": N, "falls": [[block, members in which it fell], ...]} for blocks that fell in any.
  nlohmann::ordered_json json() const {
    nlohmann::ordered_json j;
    j["members"] = members;
    j["falls"] = nlohmann::ordered_json::array();
    for (std::size_t b = 0; b < falls.size(); ++b)
      if (falls[b] > 0) j["falls"].push_back({b, falls[b]});
    return j;
  }
  // The model's blocks with cell array fallen_share (0 to 1), when a member left its frames.
  void write_vtu(const fs::path& file) const {
    if (members == 0 || first_frame.empty()) return;
    write_blocks_with_value(first_frame, file, "fallen_share", [&](int b) {
      return b < static_cast<int>(falls.size()) ? double(falls[b]) / members : 0.0;
    });
  }
};

}  // namespace

std::string summary_csv_values(const nlohmann::json& summary) {
  std::ostringstream csv;
  bool first = true;
  for (const ResultColumn& c : result_columns()) {
    // A member's summary from an older program may lack a newer column: left empty.
    const nlohmann::json v = summary.contains(c.name) ? summary[c.name] : nlohmann::json();
    if (!first) csv << ',';
    first = false;
    if (v.is_boolean()) csv << (v.get<bool>() ? "yes" : "no");
    else if (v.is_string()) csv << v.get<std::string>();
    else if (!v.is_null()) csv << v.dump();
  }
  return csv.str();
}

std::array<double, 2> wilson_interval(int hits, int trials, double z) {
  if (trials <= 0) return {0.0, 1.0};
  const double n = trials, p = hits / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

nlohmann::ordered_json value_spread(const std::vector<double>& v) {
  nlohmann::ordered_json j;
  j["median"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(median(v));
  j["min"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::min_element(v.begin(), v.end()));
  j["max"] = v.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(*std::max_element(v.begin(), v.end()));
  j["count"] = v.size();
  return j;
}

std::string number_text(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

fs::path member_folder(const fs::path& out, int member) {
  char name[32];
  std::snprintf(name, sizeof name, "member_%03d", member);
  return out / name;
}

MemberStatus run_in_folder_or_throw(const fs::path& folder, const std::string& key, const std::string& name,
                                    SeismicRunOptions options, int threads, const StartRun& start,
                                    const std::function<void(const std::string&)>& event, const Scenario* started_as,
                                    SeismicRunResult* result) {
  if (outputs_current(folder, key)) {
    event(name + ": current, kept");
    return MemberStatus::current;
  }
  use_threads(threads);
  options.out = folder;
  options.on_frame = with_progress_lines(std::move(options.on_frame), name, event);
  if (!options.on_settle_frame) options.on_settle_frame = settling_lines(name, event);
  RunOverrides overrides;
  overrides.set(&RunSettings::threads, threads);
  std::unique_ptr<SeismicRun> run;
  std::string started;  // the key of the run the folder's checkpoint belongs to
  std::getline(std::ifstream(folder / "started.key"), started);
  if (started == key && fs::exists(folder / "checkpoint.bin")) {
    options.on_resume = nullptr;  // what `start` would have done is in the checkpoint
    run = SeismicRun::resume(options, overrides, {}, started_as);
    event(name + ": goes on from its checkpoint");
  }
  if (!run) {
    fs::remove_all(folder);  // no frames of an older run left behind
    fs::create_directories(folder);
    write_text_atomically(folder / "started.key", key + "\n");
    run = start(options);
    event(name + ": started");
  }
  const SeismicRunResult r = run->run();
  if (result) *result = r;
  if (r.interrupted && stop_requested()) {
    event(name + ": interrupted (its checkpoint is kept: it goes on from it)");
    return MemberStatus::interrupted;
  }
  if (!r.interrupted) fs::remove(folder / "checkpoint.bin");
  stamp_outputs(folder, key);  // last: the outputs are complete
  event(name + ": done, " + std::to_string(r.fallen_stones) + " fallen stones" + (r.collapse ? ", collapse" : ""));
  return MemberStatus::ran;
}

MemberStatus run_in_folder(const fs::path& folder, const std::string& key, const std::string& name, SeismicRunOptions options,
                           int threads, const StartRun& start, const std::function<void(const std::string&)>& event) {
  try {
    return run_in_folder_or_throw(folder, key, name, std::move(options), threads, start, event);
  } catch (const std::exception& e) {
    event(name + ": FAILED: " + e.what());
    return MemberStatus::failed;
  }
}

OutcomeCounts write_outcomes(const OutcomeTable& table, const fs::path& csv_file, nlohmann::ordered_json& j) {
  std::ostringstream csv;
  csv << "member";
  for (const std::string& name : table.draw_columns) csv << ',' << name;
  for (const ResultColumn& c : result_columns()) csv << ',' << c.name;
  csv << ",first_fall_s,stopped_early\n";  // stopped_early: ended at its collapse (stop_at), its counts at that frame
  OutcomeCounts n;
  std::map<std::string, int> modes;
  std::vector<double> fallen, first_opening, first_fall, crown_drop, hinges;
  std::vector<int> members;
  std::vector<bool> collapsed;
  FallMap fall_map;
  for (const OutcomeTable::Row& row : table.rows) {
    const nlohmann::json s = nlohmann::json::parse(std::ifstream(row.folder / "summary.json"));
    fall_map.add(s, row.folder);
    const double fall = first_fall_s(row.folder / "history.csv", s["settle_time_s"].get<double>());
    if (s.contains("failure_mode") && s["failure_mode"].is_string()) ++modes[s["failure_mode"].get<std::string>()];  // older runs: none
    csv << row.member;
    for (const std::string& draw : row.draws) csv << ',' << draw;
    csv << ',' << summary_csv_values(s) << ',' << (fall < 0 ? std::string() : std::to_string(fall)) << ','
        << (s.value("stopped_early", false) ? "yes" : "no") << '\n';  // older summaries: no such key
    ++n.finished;
    n.collapses += s["collapse"].get<bool>();
    collapsed.push_back(s["collapse"].get<bool>());
    n.stones_fell += s["fallen_stones"].get<int>() > 0;
    n.ring_stones_fell += s["fallen_ring_stones"].get<int>() > 0;
    fallen.push_back(s["fallen_stones"].get<int>());
    if (!s["first_opening_s"].is_null()) first_opening.push_back(s["first_opening_s"].get<double>());
    if (fall >= 0) first_fall.push_back(fall);
    crown_drop.push_back(s["largest_crown_drop_m"].get<double>());
    if (s.contains("most_ring_hinges") && s["most_ring_hinges"].is_number()) hinges.push_back(s["most_ring_hinges"].get<int>());
    members.push_back(row.member);
  }
  const std::size_t count = members.size();
  if (count > 0) {
    std::size_t worst = 0;
    for (std::size_t k = 1; k < count; ++k)
      if (std::tie(fallen[k], crown_drop[k]) > std::tie(fallen[worst], crown_drop[worst])) worst = k;
    n.worst = members[worst];
    const bool most_collapse = 2 * n.collapses > n.finished;  // a tie: standing, the lesser claim
    std::vector<std::size_t> common;
    for (std::size_t k = 0; k < count; ++k)
      if (collapsed[k] == most_collapse) common.push_back(k);
    std::stable_sort(common.begin(), common.end(), [&](std::size_t a, std::size_t b) { return fallen[a] < fallen[b]; });
    n.typical = members[common[(common.size() - 1) / 2]];
  }
  write_text_atomically(csv_file, csv.str());

  j["finished"] = n.finished;
  j["interval"] = "95 % Wilson score interval of each proportion";
  j["collapse"] = probability(n.collapses, n.finished);
  j["stones_fall"] = probability(n.stones_fell, n.finished);
  j["ring_stones_fall"] = probability(n.ring_stones_fell, n.finished);
  j["fallen_stones"] = value_spread(fallen);
  j["first_opening_s"] = value_spread(first_opening);  // count: the members in which a joint opened
  j["first_fall_s"] = value_spread(first_fall);
  j["largest_crown_drop_m"] = value_spread(crown_drop);
  if (!hinges.empty()) j["most_ring_hinges"] = value_spread(hinges);  // older runs and models without a ring: none
  j["most_common_outcome_member"] = n.typical;  // of the majority's verdict, the median fallen stones
  j["worst_outcome_member"] = n.worst;          // the most fallen stones, then the largest crown drop
  n.failure_modes.assign(modes.begin(), modes.end());
  std::stable_sort(n.failure_modes.begin(), n.failure_modes.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  j["failure_modes"] = nlohmann::ordered_json::object();  // members by how they fail, the most common first
  for (const auto& [mode, count] : n.failure_modes) j["failure_modes"][mode] = count;
  j["fallen_blocks"] = fall_map.json();
  fall_map.write_vtu(csv_file.parent_path() / "fallen_share.vtu");
  return n;
}

}  // namespace ishibashi
