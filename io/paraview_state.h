// A ParaView state file (view.pvsm) beside a run's series, so that the run opens ready to
// play: blocks without the ground slab, coloured by displacement relative to the ground
// on one fixed scale, fallen stones in red, cracked joints as black points, the camera on
// the bridge from a three-quarter view, the time at the first frame; tie rods, where the
// model has them, as blue lines.
//
// The series are named without a folder (blocks.pvd, contacts.pvd), so the run's folder
// can be moved or zipped: open it with File > Load State and "Search files under
// specified directory" (ParaView offers the state file's folder), with
// `paraview --state=view.pvsm` from the run's folder, or in pvpython with
// LoadState(file, data_directory=folder).
#pragma once
#include <filesystem>

#include "engine/math.h"

namespace ishibashi {

struct ParaViewView {
  Vec3 lower_m = Vec3::Zero(), upper_m = Vec3::Zero();  // the bridge's bounds, ground slab left out
  double colour_range_m = 1e-3;  // top of the colour scale: displacement relative to the ground (m)
  double first_time_s = 0, last_time_s = 0;  // of the series' frames
  bool ties = false;  // the run wrote ties.pvd: its rods drawn as blue lines
};

// Written atomically: a run stopped at any moment leaves a complete state file.
void write_paraview_state(const std::filesystem::path& file, const ParaViewView& view);

}  // namespace ishibashi
