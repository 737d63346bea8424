// The outputs of a seismic run, written as it goes: the ParaView series (blocks.pvd,
// contacts.pvd) and their state file (view.pvsm), history.csv and summary.json in the
// run's folder, each replaced atomically so that a run stopped at any moment leaves valid
// files.
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/run/checkpoint.h"
#include "analysis/run/how_it_fails.h"
#include "analysis/run/member_draw.h"
#include "analysis/run/run_result.h"
#include "engine/joints.h"
#include "engine/model.h"
#include "engine/state.h"
#include "io/ground_motion.h"
#include "io/paraview_state.h"
#include "io/run_settings.h"
#include "io/vtk_output.h"

namespace ishibashi {

// What a frame counts: the joints, how close the mortar is to cracking, and the stones
// that fell or left the model.
struct RunCounts {
  JointCounts joints;
  int fallen = 0, fallen_ring = 0;
  std::string failure_mode;  // of the stones fallen so far (how_it_fails.h, failure_mode_of)
  int ring_hinges = 0;       // the ring's hinges now (how_it_fails.h, RingHinges)
  int most_ring_hinges = -1; // the most at once so far before a ring stone fell; -1: no ring
  int left_model = 0;  // blocks that fell past the ground and were frozen there
  double bond_utilisation = -1;  // largest_bond_utilisation (joints.h); -1: no bond left
  int ties_yielded = 0;           // tie rods with a plastic elongation
  double largest_tie_tension_n = 0;  // of the tie rods now
  double peak_tie_tension_n = 0;     // the largest any reached so far
};
RunCounts count_damage(const Model& m, const State& s, const JointThresholds& thresholds, Joints& joints);
// A frame's counts into the run's result: joints, fallen stones, collapse, the rods' demand.
void take_counts(const Model& m, const RunCounts& c, SeismicRunResult& r);

// What summary.json says beyond the result: the run's settings.
struct RunDescription {
  std::string model_name;
  int monitored_block = -1;
  double dt_s = 0;                                  // the step used
  int threads = 0;                                  // at most, in a step
  double mortar_pa = 0;                             // f_t = c of the stone joints; 0: dry
  double mortar_fracture_j_m2[2] = {0, 0};          // G_f^I, G_f^II; 0, 0: a brittle bond
  std::vector<std::string> mortar_parts;            // the parts whose joints it bonds
  RunSettings settings;                             // as the run was asked for ("settings" in summary.json)
  GroundMotionPeaks ground_peaks;                   // the shaking's, by component ("ground_motion")
  struct Member {                                   // an ensemble's member ("member" in summary.json)
    int index = -1;
    MemberDraw draw;
    EnsembleSpec spec;
  } member;
};

// The shaking (s) that the summary.json in `out` reports of a run that finished; -1 where
// the folder holds no summary, or one of a run stopped, killed or under way.
double finished_shaking_s(const std::filesystem::path& out);
// The sentence of summary.json's how_it_fails in `out` (how_it_fails.h); empty where none.
std::string how_it_fails_of(const std::filesystem::path& out);

class RunRecorder {
 public:
  // `joints`: the run's, as found at the start (the ring's hinges are read from them).
  RunRecorder(std::filesystem::path out, const Model& model, const Joints& joints, std::vector<int> monitors,
              std::function<void(const std::string&)> on_warning);

  // One row of history.csv and one frame of each series, of the state now (and view.pvsm
  // rewritten, its colour scale the largest displacement so far); the ground's
  // acceleration ga and displacement gd (monitored displacements are relative to it).
  // Warns once of each block that left the model. The row's bond utilisation is the
  // largest of the state's now and `bond_utilisation_since_frame` (the run's samples since
  // the last frame: the mortar's stress swings faster than frames come). Returns the
  // frame's counts.
  RunCounts record(const char* phase, const State& s, const Vec3& ga, const Vec3& gd, Joints& joints,
                   double bond_utilisation_since_frame = -1);
  void write_summary(const RunDescription& run, const SeismicRunResult& r, const State& s, const Joints& joints,
                     bool finished) const;

  // What a checkpoint keeps of the outputs so far (CheckpointWriter or CheckpointReader).
  template <class Archive>
  void visit(Archive& a) {
    const std::size_t blocks = reported_left_.size();
    a.field(reported_left_), a.field(history_), a.field(view_.colour_range_m);
    if (reported_left_.size() != blocks) throw CheckpointError("its list of the blocks that left the model is another model's");
    falls_.visit(a);
    hinges_.visit(a);
    std::vector<double> times = blocks_.frame_times();
    a.field(times);
    if constexpr (Archive::reading) blocks_.resume(times);
    times = contacts_.frame_times();
    a.field(times);
    if constexpr (Archive::reading) contacts_.resume(times);
    if (ties_) {  // the model's: the same on a resume
      times = ties_->frame_times();
      a.field(times);
      if constexpr (Archive::reading) ties_->resume(times);
    }
  }
  // After the first frame: throws InputError when `frames` more of its size (the smallest a
  // run writes) would not fit on the output's disk.
  void refuse_frames_the_disk_cannot_hold(long frames, double interval_s) const;

 private:
  std::filesystem::path out_;
  const Model& model_;
  std::vector<int> monitors_;
  std::function<void(const std::string&)> on_warning_;
  JointThresholds thresholds_;  // 1 mm opening is a crack, 1 mm slip a slipped joint
  VtkSeriesWriter blocks_, contacts_;
  std::optional<VtkSeriesWriter> ties_;  // a model with tie rods: ties.pvd
  ParaViewView view_;
  std::string history_;  // history.csv so far
  std::vector<std::uint8_t> reported_left_;  // (nb) warned that the block left the model
  FallRecord falls_;                         // when and which way each stone fell: summary.json's how_it_fails
  RingHinges hinges_;                        // the ring's hinges until its first stone fell: the same
};

}  // namespace ishibashi
