// `ishibashi modal` end to end on model A: its first modes, modes.vtu with each block's
// labels beside the mode shapes, and the picture of the first mode along each axis.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/vtk_input.h"

namespace ishibashi {
namespace {

TEST(Modal, WritesModesWithBlockLabelsAndThePictureOfEachFirstMode) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_modal";
  std::filesystem::remove_all(out);
  const auto log = out.string() + ".log";
  const std::string cmd = std::string(ISHIBASHI_BINARY) + " modal " + ISHIBASHI_SOURCE_DIR + "/models/nishida_a.toml --modes 4 --out " +
                          out.string() + " > " + log + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::stringstream printed;
  printed << std::ifstream(log).rdbuf();
  // Model A's first modes along x, y and z by modal analysis: 22.53, 20.99, 41.91 Hz.
  EXPECT_NE(printed.str().find("x 22.52"), std::string::npos) << printed.str();
  EXPECT_NE(printed.str().find("mode shapes: "), std::string::npos) << printed.str();

  vtkUnstructuredGrid* modes = read_vtu(out / "modes.vtu");
  for (const char* name : {"block_id", "part", "course", "fixed"}) EXPECT_NE(modes->GetCellData()->GetArray(name), nullptr) << name;
  for (const char* name : {"mode_1", "mode_4"}) EXPECT_NE(modes->GetPointData()->GetArray(name), nullptr) << name;
  modes->Delete();
  ASSERT_TRUE(std::filesystem::exists(out / "mode_shapes.png"));
  EXPECT_GT(std::filesystem::file_size(out / "mode_shapes.png"), 20000u);  // three modes, two views each
}

}  // namespace
}  // namespace ishibashi
