// The demo command end to end: its .pvd series opens with VTK's own readers.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkUnstructuredGrid.h>

#include "apps/demo.h"
#include "command_line.h"
#include "io/vtk_input.h"

namespace ishibashi {
namespace {

TEST(Demo, ShakeWritesASeriesThatVtkReads) {
  DemoOptions o;
  o.out = std::filesystem::temp_directory_path() / "ishibashi_demo_test";
  std::filesystem::remove_all(o.out);
  o.duration_s = 1.4;
  o.frames_per_s = 10;
  o.courses = 3;
  o.stones_per_course = 4;
  ASSERT_EQ(run_demo(o), 0);
  const auto entries = read_pvd(o.out / "blocks.pvd");
  ASSERT_EQ(entries.size(), 15u);
  for (const auto& e : entries) {
    vtkUnstructuredGrid* grid = read_vtu(e.file);
    EXPECT_EQ(grid->GetNumberOfCells(), 1 + 4 + 3 + 4);
    EXPECT_NE(grid->GetCellData()->GetArray("displacement"), nullptr);
    grid->Delete();
  }
  // The base was shaken: the last frame shows it displaced.
  vtkUnstructuredGrid* last = read_vtu(entries.back().file);
  EXPECT_GT(std::abs(last->GetCellData()->GetArray("displacement")->GetComponent(0, 0)), 1e-4);
  last->Delete();
}

// The tilt demo's base does no work: its balance is told against the energy the dashpots
// and friction took (it said -2e+26 % "of the work in", a division by the zero work).
TEST(Demo, TiltsBalanceIsASmallShareOfTheEnergyExchanged) {
  const auto out = std::filesystem::temp_directory_path() / "ishibashi_demo_tilt";
  int status = 0;
  const std::string log = test::run_command(test::program() + " demo --scene tilt --duration 0.3 --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const std::size_t at = log.find(" % of the energy exchanged)");
  ASSERT_NE(at, std::string::npos) << log;
  const double percent = std::stod(log.substr(log.rfind('(', at) + 1));
  EXPECT_LT(std::abs(percent), 1.0) << log;
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace ishibashi
