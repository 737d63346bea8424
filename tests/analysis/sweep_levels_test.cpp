// A sweep's intensity levels against hand arithmetic: pga_g scales each record so that the
// larger peak of its horizontal components is the level.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/batch/sweep_table.h"
#include "run_scenes.h"

namespace ishibashi {
namespace {

using test::kG;

// A stone on a slab under accelerations held constant: x at 0.1 g, y at -0.15 g (the larger
// horizontal peak: a magnitude) and z at 0.5 g (vertical: not counted). Swept at 0.3 g, the
// record is scaled by 0.3 / 0.15 = 2, and the run is shaken at 0.2 g, 0.3 g and 1 g.
TEST(SweepLevels, APgaLevelScalesTheLargerHorizontalPeakToIt) {
  const auto dir = test::tmp_dir() / "ishibashi_sweep_pga";
  std::filesystem::remove_all(dir);
  test::scene(dir, test::stone_and_slab(dir), "[run]\nthreads = 1\nsettle_max_s = 0.02\noutput_interval_s = 0.01\n", {0, 0});
  auto held = [&](const char* name, double g_share) {  // 0.1 s of samples 1 ms apart
    std::ofstream samples(dir / name);
    for (int k = 0; k <= 100; ++k) samples << g_share << '\n';
    return "{ file = \"" + (dir / name).string() + "\", format = \"columns\", unit = \"g\", dt_s = 0.001 }";
  };
  std::ofstream(dir / "sweep.toml") << "[sweep]\nscenario = \"" << (dir / "scene.toml").string()
                                    << "\"\nduration_s = 0.05\npga_g = [0.3]\n[failure]\ncollapse = true\n"
                                    << "[[record]]\nname = \"held\"\nstart_s = 0\nx = " << held("x.txt", 0.1)
                                    << "\ny = " << held("y.txt", -0.15) << "\nz = " << held("z.txt", 0.5) << "\n";
  int status = 0;
  const std::string log = test::run_command(
      test::program() + " sweep " + (dir / "sweep.toml").string() + " --out " + (dir / "out").string(), &status);
  ASSERT_EQ(status, 0) << log;

  std::ifstream table(dir / "out" / "sweep.csv");
  std::string line;
  std::getline(table, line);  // the header
  ASSERT_TRUE(std::getline(table, line)) << log;
  std::vector<std::string> row;
  for (std::stringstream cells(line); std::getline(cells, line, ',');) row.push_back(line);
  EXPECT_NEAR(std::stod(row.at(sweep_column("scale_factor"))), 2.0, 1e-5);
  EXPECT_NEAR(std::stod(row.at(sweep_column("pga_g"))), 0.3, 1e-5);

  std::filesystem::path summary;
  for (const auto& run : std::filesystem::directory_iterator(dir / "out" / "runs" / "scene")) summary = run.path() / "summary.json";
  const nlohmann::json peaks = nlohmann::json::parse(std::ifstream(summary))["ground_motion"]["peak_acceleration_m_s2"];
  EXPECT_NEAR(peaks[0].get<double>(), 0.2 * kG, 1e-9);
  EXPECT_NEAR(peaks[1].get<double>(), 0.3 * kG, 1e-9);
  EXPECT_NEAR(peaks[2].get<double>(), 1.0 * kG, 1e-9);
}

}  // namespace
}  // namespace ishibashi
