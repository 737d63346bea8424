#include "analysis/run_recorder.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "geometry/bridge.h"
#include "io/atomic_file.h"

namespace ishibashi {

RunCounts count_damage(const Model& m, const State& s, const JointThresholds& thresholds, Joints& joints) {
  RunCounts c;
  c.joints = measure_joints(s, thresholds, joints);
  for (int b = 0; b < m.block_count; ++b) {
    c.left_model += s.left_model[b];
    if (is_fallen(m, s, b)) {
      ++c.fallen;
      c.fallen_ring += m.block_tag[b].part == static_cast<int>(Part::ring);
    }
  }
  return c;
}

RunRecorder::RunRecorder(std::filesystem::path out, const Model& model, std::vector<int> monitors,
                         std::function<void(const std::string&)> on_warning)
    : out_(std::move(out)),
      model_(model),
      monitors_(std::move(monitors)),
      on_warning_(std::move(on_warning)),
      blocks_(out_, "blocks"),
      contacts_(out_, "contacts", VtkSeriesWriter::Kind::contacts),
      reported_left_(model.block_count, 0) {
  std::ostringstream header;
  header << "time_s,phase,ground_ax_m_s2,ground_ay_m_s2,ground_az_m_s2,ground_dx_m,ground_dy_m,ground_dz_m";
  for (int b : monitors_) header << ",block" << b << "_dx_m,block" << b << "_dy_m,block" << b << "_dz_m";
  header << ",kinetic_j,gravitational_j,elastic_j,damping_j,friction_j,bond_j,left_model_j,ground_work_j,balance_error_j,"
            "open_joints,cracked_joints,slipped_joints,largest_opening_m,largest_slip_m,fallen_blocks,left_model_blocks\n";
  history_ = header.str();
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

RunCounts RunRecorder::record(const char* phase, const State& s, const Vec3& ga, const Vec3& gd, Joints& joints) {
  const Model& m = model_;
  const RunCounts c = count_damage(m, s, thresholds_, joints);
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
  std::ostringstream row;
  row.precision(9);
  row << s.time_s << "," << phase << "," << ga.x() << "," << ga.y() << "," << ga.z() << "," << gd.x() << "," << gd.y() << ","
      << gd.z();
  for (int b : monitors_) {
    const Vec3 d = s.position[b] - m.initial_position[b] - gd;
    row << "," << d.x() << "," << d.y() << "," << d.z();
  }
  const Energy& e = s.energy;
  row << "," << e.kinetic_j << "," << e.gravitational_j << "," << e.elastic_j << "," << e.damping_j << "," << e.friction_j
      << "," << e.bond_j << "," << e.left_model_j << "," << e.prescribed_work_j << "," << e.balance_error_j() << ","
      << c.joints.open << "," << c.joints.cracked << "," << c.joints.slipped << "," << c.joints.largest_opening_m << ","
      << c.joints.largest_slip_m << "," << c.fallen << "," << c.left_model << "\n";
  history_ += row.str();
  write_text_atomically(out_ / "history.csv", history_);
  blocks_.write(m, s, gd);
  contacts_.write(m, s, gd, &joints);
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
  auto yes = [](bool v) { return v ? "true" : "false"; };
  const JointCounts& jc = r.joint_counts;
  const int slip_joint = jc.largest_slip_joint;
  std::ostringstream j;
  j.precision(9);
  j << "{\n  \"model\": \"" << run.model_name << "\",\n  \"finished\": " << yes(finished)
    << ",\n  \"interrupted\": " << yes(r.interrupted) << ",\n  \"settled\": " << yes(r.settled)
    << ",\n  \"settle_time_s\": " << r.settle_time_s << ",\n  \"simulated_time_s\": " << s.time_s
    << ",\n  \"first_opening_time_s\": ";
  if (r.first_opening_s < 0) j << "null";
  else j << r.first_opening_s;
  j << ",\n  \"collapse\": " << yes(r.collapse) << ",\n  \"fallen_stones\": " << r.fallen_stones
    << ",\n  \"blocks_left_model\": " << r.blocks_left_model << ",\n  \"joints\": " << r.joints
    << ",\n  \"joints_open_at_end\": " << jc.open << ",\n  \"joints_cracked\": " << jc.cracked
    << ",\n  \"joints_bond_broken_while_settling\": " << r.bonds_broken_settling
    << ",\n  \"joints_slipped_at_end\": " << jc.slipped << ",\n  \"largest_opening_m\": " << jc.largest_opening_m
    << ",\n  \"largest_slip_m\": " << jc.largest_slip_m << ",\n  \"largest_slip_blocks\": ";
  if (slip_joint < 0) j << "null";
  else j << "[" << joints.block_a[slip_joint] << ", " << joints.block_b[slip_joint] << "]";
  j << ",\n  \"largest_crown_drop_m\": " << r.largest_crown_drop_m << ",\n  \"monitored_block\": " << run.monitored_block
    << ",\n  \"energy_balance_error_j\": " << r.balance_error_j
    << ",\n  \"energy_balance_error_relative\": " << r.balance_error_relative << ",\n  \"dt_s\": " << run.dt_s
    << ",\n  \"damping\": \"" << run.damping << "\""
    << ",\n  \"joint_rule\": \"" << run.joint_rule << "\""
    << ",\n  \"mortar_pa\": " << run.mortar_pa << ",\n  \"mortar_fracture_j_m2\": [" << run.mortar_fracture_j_m2[0] << ", "
    << run.mortar_fracture_j_m2[1] << "]"
    << ",\n  \"steps\": " << s.step << ",\n  \"threads\": " << run.threads
    << ",\n  \"mean_team_size\": " << (s.step > 0 ? double(s.profile.thread_steps) / s.step : 0.0) << ",\n  \"state_hash\": \""
    << std::hex << r.state_hash << std::dec << "\"" << ",\n  \"wall_time_s\": " << r.wall_s << "\n}\n";
  write_text_atomically(out_ / "summary.json", j.str());
}

std::string result_csv_header() {
  return "settled,settle_time_s,shaking_s,first_opening_s,largest_crown_drop_m,fallen_stones,collapse,joints,joints_cracked,"
         "energy_balance_pct,steps,wall_s";
}

std::string result_csv_values(const SeismicRunResult& r) {
  std::ostringstream row;
  row.precision(9);
  row << (r.settled ? "yes" : "no") << "," << r.settle_time_s << "," << r.shaking_time_s << ",";
  if (r.first_opening_s >= 0) row << r.first_opening_s;
  row << "," << r.largest_crown_drop_m << "," << r.fallen_stones << "," << (r.collapse ? "yes" : "no") << "," << r.joints
      << "," << r.joint_counts.cracked << "," << 100 * r.balance_error_relative << "," << r.steps << "," << r.wall_s;
  return row.str();
}

}  // namespace ishibashi
