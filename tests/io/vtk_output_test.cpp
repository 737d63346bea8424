// The ParaView output read back with VTK's own readers.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "io/vtk_input.h"
#include "io/vtk_output.h"
#include "scenes.h"

namespace ishibashi {
namespace {

TEST(VtkOutput, SeriesReadsBackWithBlocksAndArrays) {
  const auto dir = std::filesystem::temp_directory_path() / "ishibashi_vtk_test";
  std::filesystem::remove_all(dir);
  WallSpec spec;
  spec.courses = 2;
  spec.stones_per_course = 3;
  World w(make_wall_model(spec), 1e-5);
  VtkSeriesWriter writer(dir, "blocks");
  writer.write(w.model(), w.state());
  w.state().velocity[0] = Vec3(0.1, 0, 0);
  w.run(500);
  writer.write(w.model(), w.state());

  const auto entries = read_pvd(writer.pvd_path());
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_DOUBLE_EQ(entries[0].time_s, 0.0);
  EXPECT_NEAR(entries[1].time_s, 500 * 1e-5, 1e-12);
  vtkUnstructuredGrid* grid = read_vtu(entries[1].file);
  const Model& m = w.model();
  EXPECT_EQ(grid->GetNumberOfCells(), m.block_count);
  EXPECT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(m.vertex_local.size()));
  EXPECT_EQ(grid->GetCellType(0), VTK_POLYHEDRON);
  for (const char* name : {"block_id", "material", "fixed", "velocity", "displacement", "displacement_relative_to_ground",
                           "angular_velocity"})
    EXPECT_NE(grid->GetCellData()->GetArray(name), nullptr) << name;
  for (const char* name : {"velocity", "displacement"}) EXPECT_NE(grid->GetPointData()->GetArray(name), nullptr) << name;
  // The base moved 500 dt * 0.1 m/s = 0.5 mm: its displacement says so.
  EXPECT_NEAR(grid->GetCellData()->GetArray("displacement")->GetComponent(0, 0), 500 * 1e-5 * 0.1, 1e-9);
  EXPECT_EQ(grid->GetCellData()->GetArray("fixed")->GetComponent(0, 0), 1.0);
  EXPECT_EQ(grid->GetCellData()->GetArray("block_id")->GetComponent(3, 0), 3.0);
  grid->Delete();
  // Plain XML text, as Debian's ParaView 5.11 with the patched libexpat can parse: data
  // inline in base64, no raw or appended section (which made it fail to read every file).
  std::ifstream in(entries[1].file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("<AppendedData"), std::string::npos);
  EXPECT_NE(text.find("format=\"binary\""), std::string::npos);
  EXPECT_TRUE(std::all_of(text.begin(), text.end(), [](char ch) { return (ch >= 32 && ch < 127) || ch == '\n' || ch == '\t' || ch == '\r'; }))
      << "the .vtu holds bytes that are not XML text";
  // No temporary files are left behind.
  for (const auto& f : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(f.path().string().find(".tmp"), std::string::npos) << f.path();
}

// The contacts' bond_utilisation read back: a bonded block held in tension at half its
// strength carries 0.5 at every point (uniform tension, no shear); a dry joint pressed by
// the same load holds no bond at its points: NaN.
TEST(VtkOutput, ContactPointsCarryTheirBondUtilisation) {
  const auto dir = std::filesystem::temp_directory_path() / "ishibashi_vtk_bond_test";
  std::filesystem::remove_all(dir);
  const double a = 0.64, strength = 2e5;
  auto utilisation = [&](const Material& stone, double load_n, const char* name) {
    ModelBuilder b = test::block_on_base(Vec3(a, a, a), stone);
    b.set_gravity(Vec3::Zero());
    World w(b.build(), 2e-5);
    const Vec3 load(0, 0, load_n);
    w.state().applied_force[1] = load;
    w.state().applied_torque[1] = Vec3(0, 0, -a / 2).cross(load);  // at the joint plane: no couple
    w.run(20000);  // 0.4 s, h = 1: at rest
    VtkSeriesWriter writer(dir, name, VtkSeriesWriter::Kind::contacts);
    writer.write(w.model(), w.state());
    vtkUnstructuredGrid* grid = read_vtu(read_pvd(writer.pvd_path()).back().file);
    std::vector<double> values;
    if (vtkDataArray* array = grid->GetPointData()->GetArray("bond_utilisation"))
      for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i) values.push_back(array->GetComponent(i, 0));
    grid->Delete();
    return values;
  };
  const double half = 0.5 * strength * a * a;
  const std::vector<double> bonded = utilisation(test::stone(1.0, 33.23, strength), half, "bonded");
  ASSERT_GE(bonded.size(), 4u);
  for (double u : bonded) EXPECT_NEAR(u, 0.5, 0.005);
  const std::vector<double> dry = utilisation(test::stone(), -half, "dry");
  ASSERT_GE(dry.size(), 4u);
  for (double u : dry) EXPECT_TRUE(std::isnan(u)) << u;
}

TEST(VtkInput, MissingOrMalformedPvdIsAClearError) {
  const auto dir = std::filesystem::temp_directory_path() / "ishibashi_vtk_bad";
  std::filesystem::create_directories(dir);
  EXPECT_THROW(read_pvd(dir / "none.pvd"), std::runtime_error);
  std::ofstream(dir / "bad.pvd") << "<VTKFile type=\"UnstructuredGrid\"></VTKFile>";
  try {
    read_pvd(dir / "bad.pvd");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.pvd"), std::string::npos);
  }
}

}  // namespace
}  // namespace ishibashi
