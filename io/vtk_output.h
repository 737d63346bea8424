// ParaView output of the blocks: one inline-binary, zlib-compressed .vtu per output time (one
// polyhedron cell per block) and a .pvd collection that lists them with their times.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "engine/joints.h"
#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

// VTK makes its list of object factories on its first object, and not thread-safely: two
// threads that write their first files at once can both make it, and one list leaks
// (LeakSanitizer saw it in an ensemble of two members side by side). Called before
// threads that write VTK files start, it makes the list on the calling thread.
void make_vtk_ready_for_threads();

// Cell data: block_id, material, part and course (the generator's labels, see
// geometry/bridge.h: 0 ground, 1 ring, 2 wall, 3 fill, 4 soil, 5 side wall), fixed (1
// unless the block is free), fallen (see is_fallen in engine/state.h), velocity (m/s),
// angular_velocity (rad/s), displacement of the centroid (m) and the same relative to the
// ground (displacement_relative_to_ground: minus the ground's displacement, m, so that a
// shaken bridge is coloured by how it deforms, not by how the ground moves). Point data:
// velocity and displacement of each vertex.
void write_blocks_vtu(const Model& model, const State& state, const std::filesystem::path& file,
                      const Vec3& ground_displacement_m = Vec3::Zero());

// The sub-contacts as points (one vertex cell each), so cracks can be seen: point data
// normal (a -> b), force_n (the springs' force on b, N: glyphs of it show how the load
// runs through the stones), normal_stress_pa (tension positive), shear_stress_pa, opening_m
// (positive gap), slip_m (accumulated sliding), bond_damage, bond_utilisation (the share
// of its strength the bond carries, bond_utilisation in engine/joints.h; NaN where no bond
// holds, which ParaView leaves out of the colour range), state (0 bonded, 1 elastic, 2
// sliding, 3 open, 4 broken: lost its bond, in contact), original (1: part of a joint in
// contact at the start), block_a, block_b; with `joints`, their joint's joint_opening_m,
// joint_slip_m and joint_cracked.
void write_contacts_vtu(const Model& model, const State& state, const std::filesystem::path& file,
                        const Joints* joints = nullptr);

// The tie rods as lines between their anchors: cell data tie_id, block_a, block_b,
// tension_n (0: slack), peak_tension_n (the largest so far), plastic_elongation_m, yielded.
void write_ties_vtu(const Model& model, const State& state, const std::filesystem::path& file);

// The blocks with one point array per mode, mode_1, mode_2, ...: each vertex's
// displacement in that mode (mass-normalised), for ParaView's Warp By Vector / animation;
// cell data: the blocks' labels (block_id, material, part, course, fixed), as blocks_*.vtu.
void write_modes_vtu(const Model& model, const State& state, const Eigen::MatrixXd& shapes,
                     const std::vector<int>& free_blocks, const std::filesystem::path& file);

// The blocks of `blocks_frame` (a frame that write_blocks_vtu wrote, e.g. a run's first)
// with one more cell array, `name`: value(block_id) for each cell. For what many runs say
// of each block, such as the share of an ensemble's members in which it fell. Written
// atomically.
void write_blocks_with_value(const std::filesystem::path& blocks_frame, const std::filesystem::path& file,
                             const std::string& name, const std::function<double(int block)>& value);

// A time series <name>.pvd + <name>_NNNNNN.vtu in one folder. The .pvd is rewritten
// atomically after each frame, so a run stopped at any moment leaves a valid series.
class VtkSeriesWriter {
 public:
  enum class Kind { blocks, contacts, ties };
  VtkSeriesWriter(std::filesystem::path directory, std::string name, Kind kind = Kind::blocks);
  void write(const Model& model, const State& state, const Vec3& ground_displacement_m = Vec3::Zero(),
             const Joints* joints = nullptr);
  std::filesystem::path pvd_path() const { return directory_ / (name_ + ".pvd"); }
  int frame_count() const { return static_cast<int>(times_.size()); }
  const std::vector<double>& frame_times() const { return times_; }
  std::filesystem::path last_frame() const { return directory_ / files_.back(); }  // after a write
  // A resumed run's series: its first frames (and their files) are those of `times`;
  // the next write is frame times.size().
  void resume(const std::vector<double>& times);

 private:
  std::filesystem::path directory_;
  std::string name_;
  Kind kind_;
  std::vector<double> times_;
  std::vector<std::string> files_;
};

}  // namespace ishibashi
