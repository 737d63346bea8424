// What each array of the ParaView frames holds, read back with VTK's reader and checked
// against closed forms: a rigid block's vertex velocities and displacements, a tie rod's
// anchors, a mode's vertex displacements, and the forces, stresses, openings and states of
// a block resting, sheared, sliding and lifted on a slab.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "engine/joints.h"
#include "engine/world.h"
#include "io/vtk_input.h"
#include "io/vtk_output.h"
#include "scenes.h"

namespace ishibashi {
namespace {

std::filesystem::path fresh_folder(const char* name) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

Vec3 tuple(vtkDataArray* a, vtkIdType i) { return Vec3(a->GetComponent(i, 0), a->GetComponent(i, 1), a->GetComponent(i, 2)); }

// A fixed base (block 0, part 0) and two free 1 m cubes (blocks 1 and 2, part 1, courses 4
// and 5) centred at (0, 0, 0.5) and (2, 0, 0.5), a tie rod from (0.25, 0, 0.5) in cube 1 to
// (1.75, 0, 0.5) in cube 2.
Model two_cubes_and_a_rod() {
  ModelBuilder b;
  const int mat = b.add_material(test::stone());
  const Polyhedron base = make_box(Vec3(0, 0, -0.5), Vec3(8, 4, 1));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base", BlockTag{0, 0});
  for (int i = 0; i < 2; ++i) {
    const Polyhedron cube = make_box(Vec3(2.0 * i, 0, 0.5), Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat, Motion::free, "cube", BlockTag{1, 4 + i});
  }
  b.add_tie(Vec3(0.25, 0, 0.5), Vec3(1.75, 0, 0.5), 1e-4, 2e11, 5e8);
  return b.build();
}

// Cube 1 moved by (0.3, -0.2, 0.1) and turned a quarter turn about z, (x, y) -> (-y, x)
// about its centre, moving at (1, 2, 3) m/s and spinning at 2 rad/s about z; cube 2 dropped
// 1.2 m (more than its size: fallen), at rest.
constexpr double kSpin = 2.0;
const Vec3 kShift(0.3, -0.2, 0.1), kVelocity(1, 2, 3);
Vec3 quarter_turn(const Vec3& r) { return Vec3(-r.y(), r.x(), r.z()); }

void move_the_cubes(const Model& m, State& s) {
  const Quat turn(Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()));
  s.position[1] = m.initial_position[1] + kShift;
  s.orientation[1] = turn * m.initial_orientation[1];
  s.velocity[1] = kVelocity;
  s.angular_velocity[1] = Vec3(0, 0, kSpin);
  s.position[2] = m.initial_position[2] - Vec3(0, 0, 1.2);
}

TEST(VtkValues, ABlocksFrameHoldsEachVertexsRigidMotionAndEachBlocksLabels) {
  const auto dir = fresh_folder("ishibashi_vtk_values_blocks");
  World w(two_cubes_and_a_rod(), 1e-5);
  const Model& m = w.model();
  write_blocks_vtu(m, w.state(), dir / "start.vtu");
  move_the_cubes(m, w.state());
  const Vec3 ground(0.05, -0.01, 0);
  write_blocks_vtu(m, w.state(), dir / "moved.vtu", ground);
  vtkUnstructuredGrid* start = read_vtu(dir / "start.vtu");
  vtkUnstructuredGrid* moved = read_vtu(dir / "moved.vtu");
  ASSERT_EQ(moved->GetNumberOfCells(), 3);
  const Vec3 centre0(0, 0, 0.5), centre = centre0 + kShift;
  vtkDataArray* velocity = moved->GetPointData()->GetArray("velocity");
  vtkDataArray* displacement = moved->GetPointData()->GetArray("displacement");
  ASSERT_TRUE(velocity && displacement);
  for (vtkIdType v = m.vertex_begin[1]; v < m.vertex_begin[2]; ++v) {
    const Vec3 x0(start->GetPoint(v));
    EXPECT_NEAR(std::abs(x0.x()), 0.5, 1e-12);  // a corner of the cube as built
    EXPECT_NEAR(std::abs(x0.y()), 0.5, 1e-12);
    EXPECT_NEAR(std::abs(x0.z() - 0.5), 0.5, 1e-12);
    const Vec3 r = quarter_turn(x0 - centre0);  // from the centre, after the turn
    const Vec3 x(moved->GetPoint(v));
    EXPECT_LT((x - (centre + r)).norm(), 1e-12) << "vertex " << v;
    EXPECT_LT((tuple(displacement, v) - (centre + r - x0)).norm(), 1e-12) << "vertex " << v;
    const Vec3 rigid = kVelocity + Vec3(-kSpin * r.y(), kSpin * r.x(), 0);  // v + w x r, w along z
    EXPECT_LT((tuple(velocity, v) - rigid).norm(), 1e-12) << "vertex " << v;
  }
  vtkCellData* cells = moved->GetCellData();
  auto cell = [&](const char* name, vtkIdType c) {
    vtkDataArray* a = cells->GetArray(name);
    return a ? tuple(a, c) : Vec3(NAN, NAN, NAN);
  };
  auto scalar = [&](const char* name, vtkIdType c) {
    vtkDataArray* a = cells->GetArray(name);
    return a ? a->GetComponent(c, 0) : NAN;
  };
  EXPECT_LT((cell("velocity", 1) - kVelocity).norm(), 1e-15);
  EXPECT_LT((cell("angular_velocity", 1) - Vec3(0, 0, kSpin)).norm(), 1e-15);
  EXPECT_LT((cell("displacement", 1) - kShift).norm(), 1e-12);
  EXPECT_LT((cell("displacement_relative_to_ground", 1) - (kShift - ground)).norm(), 1e-12);
  EXPECT_LT((cell("displacement_relative_to_ground", 2) - (Vec3(0, 0, -1.2) - ground)).norm(), 1e-12);
  const double fallen[] = {0, 0, 1}, fixed[] = {1, 0, 0}, part[] = {0, 1, 1}, course[] = {0, 4, 5};
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(scalar("block_id", c), c);
    EXPECT_EQ(scalar("fallen", c), fallen[c]) << "block " << c;
    EXPECT_EQ(scalar("fixed", c), fixed[c]) << "block " << c;
    EXPECT_EQ(scalar("part", c), part[c]) << "block " << c;
    EXPECT_EQ(scalar("course", c), course[c]) << "block " << c;
  }
  start->Delete();
  moved->Delete();
}

TEST(VtkValues, ATieRodsLineRunsBetweenItsAnchorsAsTheBlocksMove) {
  const auto dir = fresh_folder("ishibashi_vtk_values_ties");
  World w(two_cubes_and_a_rod(), 1e-5);
  move_the_cubes(w.model(), w.state());
  write_ties_vtu(w.model(), w.state(), dir / "ties.vtu");
  vtkUnstructuredGrid* ties = read_vtu(dir / "ties.vtu");
  ASSERT_EQ(ties->GetNumberOfCells(), 1);
  // The anchor in cube 1, 0.25 m along x from its centre, turned onto y; cube 2's dropped.
  const Vec3 anchor_a = Vec3(0, 0, 0.5) + kShift + quarter_turn(Vec3(0.25, 0, 0));
  const Vec3 anchor_b = Vec3(1.75, 0, 0.5 - 1.2);
  EXPECT_LT((Vec3(ties->GetPoint(0)) - anchor_a).norm(), 1e-12);
  EXPECT_LT((Vec3(ties->GetPoint(1)) - anchor_b).norm(), 1e-12);
  EXPECT_EQ(ties->GetCellData()->GetArray("block_a")->GetComponent(0, 0), 1);
  EXPECT_EQ(ties->GetCellData()->GetArray("block_b")->GetComponent(0, 0), 2);
  ties->Delete();
}

TEST(VtkValues, AModesVerticesMoveAsTheirBlocksTranslationAndTurn) {
  const auto dir = fresh_folder("ishibashi_vtk_values_modes");
  World w(two_cubes_and_a_rod(), 1e-5);
  const Model& m = w.model();
  // One mode: cube 1 along x by 1 and turned 1 rad about z, cube 2 up by 2 (6 dofs each).
  Eigen::MatrixXd shapes = Eigen::MatrixXd::Zero(12, 1);
  shapes(0, 0) = 1;
  shapes(5, 0) = 1;
  shapes(8, 0) = 2;
  write_modes_vtu(m, w.state(), shapes, {1, 2}, dir / "modes.vtu");
  vtkUnstructuredGrid* modes = read_vtu(dir / "modes.vtu");
  vtkDataArray* mode = modes->GetPointData()->GetArray("mode_1");
  ASSERT_NE(mode, nullptr);
  for (vtkIdType v = 0; v < modes->GetNumberOfPoints(); ++v) {
    const Vec3 x(modes->GetPoint(v));
    Vec3 expected = Vec3::Zero();  // the base, not among the free blocks
    if (v >= m.vertex_begin[1] && v < m.vertex_begin[2]) expected = Vec3(1 - x.y(), x.x(), 0);  // t + z x (x - c), c on the z axis
    if (v >= m.vertex_begin[2]) expected = Vec3(0, 0, 2);
    EXPECT_LT((tuple(mode, v) - expected).norm(), 1e-12) << "vertex " << v;
  }
  modes->Delete();
}

// A 1 x 1 x 0.5 m block (940 kg) on a slab, loaded at its joint's plane (no couple), and
// its contact points' frame written and read back.
struct RestingBlock {
  static constexpr double kArea = 1.0, kHeight = 0.5;
  std::filesystem::path dir = fresh_folder("ishibashi_vtk_values_contacts");
  World world{test::block_on_base(Vec3(1, 1, kHeight), test::stone()).build(), 2e-5};
  double weight_n() const { return world.model().mass_kg[1] * 9.81; }
  void load(const Vec3& force) {
    world.state().applied_force[1] = force;
    world.state().applied_torque[1] = Vec3(0, 0, -0.5 * kHeight).cross(force);
  }
  vtkUnstructuredGrid* contacts(const char* name, const Joints* joints = nullptr) {
    const auto file = dir / name;
    write_contacts_vtu(world.model(), world.state(), file, joints);
    return read_vtu(file);
  }
};

// Every point's value of `name`, checked by `check(value, point)`.
void each_point(vtkUnstructuredGrid* grid, const char* name, const std::function<void(double, vtkIdType)>& check) {
  vtkDataArray* a = grid->GetPointData()->GetArray(name);
  ASSERT_NE(a, nullptr) << name;
  ASSERT_GE(a->GetNumberOfTuples(), 4) << name;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) check(a->GetComponent(i, 0), i);
}

TEST(VtkValues, AContactsFrameGivesAHeldAndASlidingBlocksStresses) {
  RestingBlock block;
  const double w = block.weight_n(), tan_phi = std::tan(33.23 * M_PI / 180);
  ASSERT_NEAR(w, 1880 * 0.5 * 9.81, 1e-6);
  // At rest under a shear of 0.3 W: uniform stresses, sigma = -W / A (tension positive),
  // tau = 0.3 W / A, the points stuck (1).
  block.load(Vec3(0.3 * w, 0, 0));
  block.world.run(20000);
  vtkUnstructuredGrid* held = block.contacts("held.vtu");
  each_point(held, "normal_stress_pa", [&](double s, vtkIdType i) { EXPECT_NEAR(s, -w / RestingBlock::kArea, 1e-3 * w) << i; });
  each_point(held, "shear_stress_pa", [&](double t, vtkIdType i) { EXPECT_NEAR(t, 0.3 * w / RestingBlock::kArea, 1e-3 * w) << i; });
  each_point(held, "state", [](double code, vtkIdType i) { EXPECT_EQ(code, 1) << i; });
  each_point(held, "opening_m", [](double o, vtkIdType i) { EXPECT_EQ(o, 0) << i; });
  each_point(held, "block_a", [](double a, vtkIdType i) { EXPECT_EQ(a, 0) << i; });
  each_point(held, "block_b", [](double b, vtkIdType i) { EXPECT_EQ(b, 1) << i; });
  vtkDataArray* normal = held->GetPointData()->GetArray("normal");
  for (vtkIdType i = 0; i < normal->GetNumberOfTuples(); ++i) EXPECT_LT((tuple(normal, i) - Vec3::UnitZ()).norm(), 1e-9);
  // The slab's forces on the block hold it: W up, 0.3 W against the push.
  vtkDataArray* force = held->GetPointData()->GetArray("force_n");
  ASSERT_NE(force, nullptr);
  Vec3 total = Vec3::Zero();
  for (vtkIdType i = 0; i < force->GetNumberOfTuples(); ++i) total += tuple(force, i);
  EXPECT_LT((total - Vec3(-0.3 * w, 0, w)).norm(), 1e-3 * w);
  held->Delete();
  // Pushed at 0.9 W, beyond friction: it slides (2), each point's shear stress at
  // tan(phi) |sigma|. (The block accelerates: its inertia, at the centroid, loads its front
  // points more than its back ones, and the mean stays -W / A.)
  block.load(Vec3(0.9 * w, 0, 0));
  block.world.run(2500);
  vtkUnstructuredGrid* sliding = block.contacts("sliding.vtu");
  each_point(sliding, "state", [](double code, vtkIdType i) { EXPECT_EQ(code, 2) << i; });
  vtkDataArray* sigma = sliding->GetPointData()->GetArray("normal_stress_pa");
  double mean_sigma = 0;
  for (vtkIdType i = 0; i < sigma->GetNumberOfTuples(); ++i) mean_sigma += sigma->GetComponent(i, 0) / sigma->GetNumberOfTuples();
  EXPECT_NEAR(mean_sigma, -w / RestingBlock::kArea, 1e-2 * w);
  each_point(sliding, "shear_stress_pa", [&](double t, vtkIdType i) {
    EXPECT_NEAR(t, -tan_phi * sigma->GetComponent(i, 0), 1e-6 * w) << i;
  });
  each_point(sliding, "slip_m", [](double s, vtkIdType i) { EXPECT_GT(s, 1e-4) << i; });
  sliding->Delete();
}

TEST(VtkValues, AContactsFrameGivesALiftedBlocksOpeningAndItsJointsMeasures) {
  RestingBlock block;
  Joints joints = find_original_joints(block.world.state());  // as built, in contact
  ASSERT_EQ(joints.size(), 1);
  // Lifted by 2 W from as built: open (3), each point's opening the block's height above
  // the slab (it rises without turning).
  const double w = block.weight_n();
  block.load(Vec3(0, 0, 2 * w));
  block.world.run(300);
  // The points were measured at the pose the last step started from, before it moved the
  // block by v dt (semi-implicit Euler).
  const State& s = block.world.state();
  const double lift = s.position[1].z() - s.velocity[1].z() * block.world.dt_s() - 0.5 * RestingBlock::kHeight;
  ASSERT_GT(lift, 1e-5);
  measure_joints(s, JointThresholds{}, joints);  // at the pose now
  const double lift_now = s.position[1].z() - 0.5 * RestingBlock::kHeight;
  ASSERT_NEAR(joints.opening_m[0], lift_now, 1e-3 * lift_now);
  vtkUnstructuredGrid* lifted = block.contacts("lifted.vtu", &joints);
  each_point(lifted, "state", [](double code, vtkIdType i) { EXPECT_EQ(code, 3) << i; });
  each_point(lifted, "opening_m", [&](double o, vtkIdType i) { EXPECT_NEAR(o, lift, 1e-3 * lift) << i; });
  each_point(lifted, "normal_stress_pa", [](double s, vtkIdType i) { EXPECT_EQ(s, 0) << i; });
  each_point(lifted, "joint_opening_m", [&](double o, vtkIdType i) { EXPECT_EQ(o, joints.opening_m[0]) << i; });
  each_point(lifted, "joint_cracked", [&](double c, vtkIdType i) { EXPECT_EQ(c, joints.cracked[0]) << i; });
  lifted->Delete();
}

}  // namespace
}  // namespace ishibashi
