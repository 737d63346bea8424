#include "analysis/run/run_recorder.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "geometry/bridge.h"
#include "geometry/input_error.h"
#include "io/atomic_file.h"

namespace ishibashi {

void take_counts(const Model& m, const RunCounts& c, SeismicRunResult& r) {
  r.joint_counts = c.joints;
  r.fallen_stones = c.fallen;
  r.fallen_ring_stones = c.fallen_ring;
  r.failure_mode = c.failure_mode;
  r.most_ring_hinges = c.most_ring_hinges;
  r.blocks_left_model = c.left_model;
  r.collapse = c.fallen_ring > 0 || c.fallen > 0.05 * m.block_count;
  r.tie_rods = static_cast<int>(m.ties.size());
  r.ties_yielded = c.ties_yielded;
  r.peak_tie_tension_n = c.peak_tie_tension_n;
}

RunCounts count_damage(const Model& m, const State& s, const JointThresholds& thresholds, Joints& joints) {
  RunCounts c;
  c.joints = measure_joints(s, thresholds, joints);
  c.bond_utilisation = largest_bond_utilisation(m, s);
  for (std::size_t t = 0; t < m.ties.size(); ++t) {
    c.ties_yielded += s.tie_plastic_m[t] > 0;
    c.largest_tie_tension_n = std::max(c.largest_tie_tension_n, s.tie_tension_n[t]);
    c.peak_tie_tension_n = std::max(c.peak_tie_tension_n, s.tie_peak_tension_n[t]);
  }
  for (int b = 0; b < m.block_count; ++b) {
    c.left_model += s.left_model[b];
    if (is_fallen(m, s, b)) {
      ++c.fallen;
      c.fallen_ring += m.block_tag[b].part == static_cast<int>(Part::ring);
    }
  }
  return c;
}

namespace {

// What a row of history.csv reads: the state's energies and the frame's counts.
struct HistoryFrame {
  double time_s;
  const char* phase;
  Vec3 ground_accel_m_s2, ground_displacement_m;
  const Energy& e;
  const RunCounts& c;
  std::vector<Vec3> monitored_m;  // of each monitored block, relative to the ground
};
struct HistoryColumn {
  const char* name;
  OutputValue (*value)(const HistoryFrame& f);
};
using F = HistoryFrame;
using V = OutputValue;
// history.csv's columns, listed once; the monitored blocks' displacements relative to the
// ground (block<b>_dx_m, _dy_m, _dz_m) come after the column named kMonitorsAfter. The
// counts have the names of summary.json's (result_columns) where they are the same quantity.
const HistoryColumn kHistoryColumns[] = {
    {"time_s", [](const F& f) -> V { return f.time_s; }},
    {"phase", [](const F& f) -> V { return std::string(f.phase); }},
    {"ground_ax_m_s2", [](const F& f) -> V { return f.ground_accel_m_s2.x(); }},
    {"ground_ay_m_s2", [](const F& f) -> V { return f.ground_accel_m_s2.y(); }},
    {"ground_az_m_s2", [](const F& f) -> V { return f.ground_accel_m_s2.z(); }},
    {"ground_dx_m", [](const F& f) -> V { return f.ground_displacement_m.x(); }},
    {"ground_dy_m", [](const F& f) -> V { return f.ground_displacement_m.y(); }},
    {"ground_dz_m", [](const F& f) -> V { return f.ground_displacement_m.z(); }},
    {"kinetic_j", [](const F& f) -> V { return f.e.kinetic_j; }},
    {"gravitational_j", [](const F& f) -> V { return f.e.gravitational_j; }},
    {"elastic_j", [](const F& f) -> V { return f.e.elastic_j; }},
    {"damping_j", [](const F& f) -> V { return f.e.damping_j; }},
    {"friction_j", [](const F& f) -> V { return f.e.friction_j; }},
    {"bond_j", [](const F& f) -> V { return f.e.bond_j; }},
    {"tie_yield_j", [](const F& f) -> V { return f.e.tie_yield_j; }},
    {"left_model_j", [](const F& f) -> V { return f.e.left_model_j; }},
    {"ground_work_j", [](const F& f) -> V { return f.e.prescribed_work_j; }},  // the prescribed blocks' work
    {"reclip_j", [](const F& f) -> V { return f.e.reclip_j; }},  // made by re-clips (Energy::reclip_j)
    {"balance_error_j", [](const F& f) -> V { return f.e.balance_error_j(); }},
    {"joints_open", [](const F& f) -> V { return (long long)f.c.joints.open; }},
    {"joints_cracked", [](const F& f) -> V { return (long long)f.c.joints.cracked; }},
    {"joints_slipped", [](const F& f) -> V { return (long long)f.c.joints.slipped; }},
    {"largest_opening_m", [](const F& f) -> V { return f.c.joints.largest_opening_m; }},
    {"largest_slip_m", [](const F& f) -> V { return f.c.joints.largest_slip_m; }},
    {"fallen_stones", [](const F& f) -> V { return (long long)f.c.fallen; }},
    {"blocks_left_model", [](const F& f) -> V { return (long long)f.c.left_model; }},
    {"bond_utilisation", [](const F& f) -> V {  // empty: no bond left
       if (f.c.bond_utilisation < 0) return {};
       return f.c.bond_utilisation;
     }},
    {"ties_yielded", [](const F& f) -> V { return (long long)f.c.ties_yielded; }},
    {"largest_tie_tension_n", [](const F& f) -> V { return f.c.largest_tie_tension_n; }},
    {"ring_hinges", [](const F& f) -> V { return (long long)f.c.ring_hinges; }},
};
constexpr const char* kMonitorsAfter = "ground_dz_m";

std::string history_header(const std::vector<int>& monitors) {
  std::string header;
  for (const HistoryColumn& c : kHistoryColumns) {
    if (!header.empty()) header += ',';
    header += c.name;
    if (std::strcmp(c.name, kMonitorsAfter) == 0)
      for (int b : monitors)
        for (const char* axis : {"x", "y", "z"}) header.append(",block").append(std::to_string(b)).append("_d").append(axis).append("_m");
  }
  return header + "\n";
}

std::string history_row(const HistoryFrame& frame) {
  std::string row;
  for (const HistoryColumn& c : kHistoryColumns) {
    if (!row.empty()) row += ',';
    row += csv_field(c.value(frame));
    if (std::strcmp(c.name, kMonitorsAfter) == 0)
      for (const Vec3& d : frame.monitored_m)
        for (int axis = 0; axis < 3; ++axis) row.append(",").append(csv_field(d[axis]));
  }
  return row + "\n";
}

}  // namespace

RunRecorder::RunRecorder(std::filesystem::path out, const Model& model, const Joints& joints, std::vector<int> monitors,
                         std::function<void(const std::string&)> on_warning)
    : out_(std::move(out)),
      model_(model),
      monitors_(std::move(monitors)),
      on_warning_(std::move(on_warning)),
      blocks_(out_, "blocks"),
      contacts_(out_, "contacts", VtkSeriesWriter::Kind::contacts),
      reported_left_(model.block_count, 0),
      falls_(model.block_count),
      hinges_(model, joints) {
  if (!model.ties.empty()) ties_.emplace(out_, "ties", VtkSeriesWriter::Kind::ties);
  view_.ties = ties_.has_value();
  history_ = history_header(monitors_);
  // The camera frames the bridge as built; the ground slab reaches far beyond it.
  view_.lower_m = Vec3::Constant(1e30);
  view_.upper_m = Vec3::Constant(-1e30);
  for (int b = 0; b < model.block_count; ++b) {
    if (model.block_tag[b].part == static_cast<int>(Part::ground)) continue;
    const Vec3 half = Vec3::Constant(0.5 * model.size_m[b]);
    view_.lower_m = view_.lower_m.cwiseMin(model.initial_position[b] - half);
    view_.upper_m = view_.upper_m.cwiseMax(model.initial_position[b] + half);
  }
  if (view_.lower_m.x() > view_.upper_m.x()) view_.lower_m = view_.upper_m = Vec3::Zero();
}

// A run whose frames cannot fit on its disk (an output interval of a step, a small disk) is
// stopped at its first frame, not hours later when the disk fills. The first frame is the
// smallest a run writes (nothing has moved yet, so it compresses best: model A's 65 KB
// against about 230 KB once shaking) and the caller counts the shaking's frames alone
// (settling may end early), so the refusal is never a false alarm.
void RunRecorder::refuse_frames_the_disk_cannot_hold(long frames, double interval_s) const {
  const double frame_bytes = static_cast<double>(std::filesystem::file_size(blocks_.last_frame()) +
                                                  std::filesystem::file_size(contacts_.last_frame()));
  const double need = static_cast<double>(frames) * frame_bytes;
  std::error_code ec;
  const std::filesystem::space_info disk = std::filesystem::space(out_, ec);
  if (ec || need <= static_cast<double>(disk.available)) return;
  char text[400];
  std::snprintf(text, sizeof text,
                ": the shaking's %ld frames (a frame every %.3g s) need at least %.1f GB (%.3g MB a frame: the first, "
                "which compresses best), and this disk has %.1f GB free; raise output_interval_s (--output-interval) "
                "or give the run another --out",
                frames, interval_s, need / 1e9, frame_bytes / 1e6, static_cast<double>(disk.available) / 1e9);
  throw InputError(out_.string() + text);
}

RunCounts RunRecorder::record(const char* phase, const State& s, const Vec3& ga, const Vec3& gd, Joints& joints,
                              double bond_utilisation_since_frame) {
  const Model& m = model_;
  RunCounts c = count_damage(m, s, thresholds_, joints);
  c.bond_utilisation = std::max(c.bond_utilisation, bond_utilisation_since_frame);
  for (int b = 0; b < m.block_count; ++b)
    if (s.left_model[b] && !reported_left_[b]) {
      reported_left_[b] = 1;
      if (on_warning_) {
        char text[300];
        std::snprintf(text, sizeof text, "%s fell past the edge of the ground by t = %.3f s and was frozen at (%.2f, %.2f, %.2f) m",
                      m.block_label(b).c_str(), s.time_s, s.position[b].x(), s.position[b].y(), s.position[b].z());
        on_warning_(text);
      }
    }
  falls_.note(m, s, gd);
  c.ring_hinges = hinges_.note(joints, s.time_s, c.fallen_ring > 0);
  c.most_ring_hinges = hinges_.most();
  c.failure_mode = failure_mode_of(falls_.summary(m, 0.0));  // the order of the parts' falls, not their times
  HistoryFrame frame{s.time_s, phase, ga, gd, s.energy, c, {}};
  for (int b : monitors_) frame.monitored_m.push_back(s.position[b] - m.initial_position[b] - gd);
  // The frames before the history's row: a write that fails (a full disk) stops the run
  // with no row in history.csv for a frame that is not on disk.
  blocks_.write(m, s, gd);
  contacts_.write(m, s, gd, &joints);
  if (ties_) ties_->write(m, s, gd);
  history_ += history_row(frame);
  write_text_atomically(out_ / "history.csv", history_);
  // One colour scale for the whole run: the largest displacement of a stone still standing
  // (fallen ones are drawn apart, and would squash the scale).
  for (int b = 0; b < m.block_count; ++b)
    if (m.block_tag[b].part != static_cast<int>(Part::ground) && !is_fallen(m, s, b))
      view_.colour_range_m = std::max(view_.colour_range_m, (s.position[b] - m.initial_position[b] - gd).norm());
  view_.first_time_s = blocks_.frame_times().front();
  view_.last_time_s = blocks_.frame_times().back();
  write_paraview_state(out_ / "view.pvsm", view_);
  return c;
}

void RunRecorder::write_summary(const RunDescription& run, const SeismicRunResult& r, const State& s, const Joints& joints,
                                bool finished) const {
  using Json = nlohmann::ordered_json;
  Json j;
  j["model"] = run.model_name;
  j["finished"] = finished;
  j["stopped_early"] = r.stopped_early;  // finished before the record's end: a sweep's failure decided
  for (const ResultColumn& column : result_columns())
    j[column.name] = std::visit(
        [](const auto& v) -> Json {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) return nullptr;
          else return v;
        },
        column.value(r));
  j["simulated_time_s"] = s.time_s;
  j["wall_time_s"] = r.wall_s;  // wall_s by its earlier name, which the shared 16-core scaling script reads
  j["output_wall_s"] = r.output_wall_s;  // of wall_s, recording frames (--output-interval sets how many)
  const int slip_joint = r.joint_counts.largest_slip_joint;
  j["largest_slip_blocks"] = slip_joint < 0 ? Json() : Json::array({joints.block_a[slip_joint], joints.block_b[slip_joint]});
  // The stones fallen_stones counts, by block id (an ensemble maps how often each falls).
  Json fallen = Json::array();
  for (int b = 0; b < model_.block_count; ++b)
    if (is_fallen(model_, s, b)) fallen.push_back(b);
  j["fallen_blocks"] = fallen;
  j["how_it_fails"] = how_it_fails(model_, falls_, hinges_, r.settle_time_s);
  j["monitored_block"] = run.monitored_block;
  j["dt_s"] = run.dt_s;  // the step used (settings.dt_s: the one asked for, 0 a share of the limit)
  const GroundMotionPeaks& peaks = run.ground_peaks;  // x, y, z: what a fragility takes as the intensity
  auto xyz = [](const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); };
  j["ground_motion"] = {{"peak_acceleration_m_s2", xyz(peaks.accel_m_s2)},
                        {"peak_velocity_m_s", xyz(peaks.velocity_m_s)},
                        {"peak_displacement_m", xyz(peaks.displacement_m)}};
  j["mortar_pa"] = run.mortar_pa;
  j["mortar_fracture_j_m2"] = {run.mortar_fracture_j_m2[0], run.mortar_fracture_j_m2[1]};
  j["mortar_parts"] = run.mortar_parts;
  // Each tie rod's demand (the result's columns give their count, how many yielded and the
  // largest tension any reached).
  const double plastic = s.tie_plastic_m.empty() ? 0 : *std::max_element(s.tie_plastic_m.begin(), s.tie_plastic_m.end());
  std::vector<double> yield_force;
  for (const Tie& tie : model_.ties) yield_force.push_back(tie.yield_force_n);
  j["ties"] = {{"largest_plastic_elongation_m", plastic}, {"peak_tension_by_rod_n", s.tie_peak_tension_n},
               {"yield_force_by_rod_n", yield_force}};
  j["threads"] = run.threads;
  j["mean_team_size"] = s.step > 0 ? double(s.profile.thread_steps) / s.step : 0.0;
  // Where the steps' time went (settling included): run --profile's table.
  Json& stages = j["stages"];
  for (int k = 0; k < kStageCount; ++k) {
    const StageTime& t = s.profile.stages[k];
    if (t.wall_s == 0) continue;
    Json& stage = stages[kStageNames[k]];
    stage["wall_s"] = t.wall_s;
    if (!s.profile.threads_timed) continue;
    stage["work_s"] = t.work_s;
    stage["wait_s"] = t.wait_s();
    stage["serial_s"] = t.serial_s;
    stage["imbalance"] = t.imbalance();
    stage["stolen_share"] = t.stolen_share();
    if (static_cast<Stage>(k) == Stage::narrowphase_law) stage["contact_law_work_s"] = t.law_work_s;
  }
  if (run.member.index >= 0) {
    Json& member = j["member"];
    member["index"] = run.member.index;
    member["seed"] = run.member.spec.seed;
    member["position_tolerance_m"] = run.member.spec.position_tolerance_m;
    member["amplitude"] = run.member.draw.amplitude;
    member["friction_angle_deg"] = run.member.draw.friction_angle_deg > 0 ? Json(run.member.draw.friction_angle_deg) : Json();
  }
  Json& settings = j["settings"];
  for_each_run_setting([&](const SettingInfo& info, auto member) { settings[info.key] = setting_value(run.settings.*member); });
  write_text_atomically(out_ / "summary.json", j.dump(2) + "\n");
}

double finished_shaking_s(const std::filesystem::path& out) {
  std::ifstream in(out / "summary.json");
  if (!in) return -1;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.value("finished", false)) return -1;
  return j.value("shaking_time_s", 0.0);
}

std::string how_it_fails_of(const std::filesystem::path& out) {
  std::ifstream in(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.contains("how_it_fails")) return "";
  return j["how_it_fails"].value("text", "");
}

}  // namespace ishibashi
