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

#include "command_line.h"
#include "io/vtk_input.h"

namespace ishibashi {
namespace {

// The folder's name has what a shell would split or expand: the picture's script gets it as
// it is (it was once handed over through the shell, inside double quotes).
TEST(Modal, WritesModesWithBlockLabelsAndThePictureOfEachFirstMode) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi modal $HOME \"q\"";
  std::filesystem::remove_all(out);
  const auto log = std::filesystem::temp_directory_path() / "ishibashi_modal.log";
  const std::string cmd = test::program() + " modal " + ISHIBASHI_SOURCE_DIR + "/models/nishida_a.toml --modes 4 --out '" +
                          out.string() + "' > " + log.string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::stringstream printed;
  printed << std::ifstream(log).rdbuf();
  // Model A's first modes along x, y and z by modal analysis: 22.53, 20.99, 41.91 Hz.
  EXPECT_NE(printed.str().find("x 22.52"), std::string::npos) << printed.str();
  EXPECT_NE(printed.str().find("mode shapes: "), std::string::npos) << printed.str();
  EXPECT_EQ(printed.str().find("modes at 0 Hz"), std::string::npos) << printed.str();  // the ring stands on its ground

  vtkUnstructuredGrid* modes = read_vtu(out / "modes.vtu");
  for (const char* name : {"block_id", "part", "course", "fixed"}) EXPECT_NE(modes->GetCellData()->GetArray(name), nullptr) << name;
  for (const char* name : {"mode_1", "mode_4"}) EXPECT_NE(modes->GetPointData()->GetArray(name), nullptr) << name;
  modes->Delete();
  ASSERT_TRUE(std::filesystem::exists(out / "mode_shapes.png"));
  EXPECT_GT(std::filesystem::file_size(out / "mode_shapes.png"), 20000u);  // three modes, two views each
}


// A block that touches nothing: its six modes are at 0 Hz, and modal says why.
TEST(Modal, UnsupportedBlocksAreNamedAsRigidBodyModes) {
  const auto dir = std::filesystem::temp_directory_path() / "ishibashi_modal_free";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cube.off") << "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                                  << "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  std::ofstream(dir / "cube.toml") << "[model]\nname = \"cube\"\n[import]\nfiles = [\"cube.off\"]\n";
  const auto log = dir / "modal.log";
  const std::string cmd = test::program() + " modal " + (dir / "cube.toml").string() + " --out " +
                          (dir / "out").string() + " > " + log.string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::stringstream printed;
  printed << std::ifstream(log).rdbuf();
  EXPECT_NE(printed.str().find("warning: 6 modes at 0 Hz: blocks move as rigid bodies that no joint holds"), std::string::npos)
      << printed.str();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ishibashi
