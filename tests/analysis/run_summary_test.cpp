// What a seismic run's summary.json says of its tie rods, against the closed form of a stone
// hanging on a rod that yields.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "run_scenes.h"

namespace ishibashi {
namespace {

using test::kG;

// A beam (2.5 x 1 x 0.3 m) lies across two fixed pillars; a 0.5 m cube (250 kg) hangs under
// its middle, touching it, on rod 1 (0.2 m long), whose yield force is half the cube's
// weight; a stone rests on the beam, tied to it by rod 2, which stays slack. Rod 1
// stretches elastically while the cube falls at g, x = (g / w^2)(1 - cos w t) with
// w^2 = k / m, until its tension reaches F_y = k x at w t1 = pi / 3 (cos = 1 - F_y / m g
// = 1/2), the cube then at v1 = (g / w) sin(pi / 3); from there the rod pulls F_y and
// lengthens for good while the cube falls at g - F_y / m: its plastic elongation after t
// is v1 (t - t1) + (g / 4)(t - t1)^2.
TEST(RunSummary, ATieRodsLargestPlasticElongationIsTheYieldingRodsClosedForm) {
  const auto dir = test::tmp_dir() / "ishibashi_summary_ties";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  test::box_off_file(dir / "left.off", {-1.25, -0.5, -1}, {0.5, 1, 2});
  test::box_off_file(dir / "right.off", {0.75, -0.5, -1}, {0.5, 1, 2});
  test::box_off_file(dir / "beam.off", {-1.25, -0.5, 1}, {2.5, 1, 0.3});
  test::box_off_file(dir / "cube.off", {-0.25, -0.25, 0.5}, {0.5, 0.5, 0.5});
  test::box_off_file(dir / "stone.off", {0.25, -0.25, 1.3}, {0.5, 0.5, 0.3});
  const double mass = 250, diameter = 0.01, area = 0.25 * std::numbers::pi * diameter * diameter;
  const double yield_force = 0.5 * mass * kG, k = 2e11 * area / 0.2;
  std::ostringstream model;
  model.precision(17);
  auto file = [&](const char* name) { return "\"" + (dir / name).string() + "\""; };
  model << "[import]\nfiles = [" << file("beam.off") << ", " << file("cube.off") << ", " << file("stone.off")
        << "]\nfixed_files = [" << file("left.off") << ", " << file("right.off") << "]\n"
        << "[[tie]]\nfrom = [0, 0, 1.1]\nto = [0, 0, 0.9]\ndiameter_m = " << diameter << "\nyield_pa = " << yield_force / area
        << "\n[[tie]]\nfrom = [0.5, 0, 1.2]\nto = [0.5, 0, 1.4]\ndiameter_m = " << diameter << "\n";
  const std::string run = "[run]\nthreads = 1\nsettle_max_s = 0.1\nstop_at = \"end\"\n";
  test::run_into(dir / "out", test::scene(dir, model.str(), run, std::vector<double>(201, 0.0)));

  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  const double t = summary["simulated_time_s"].get<double>(), w = std::sqrt(k / mass);
  ASSERT_NEAR(t, 0.3, 1e-3);
  const double t1 = std::numbers::pi / 3 / w, v1 = kG / w * std::sin(std::numbers::pi / 3);
  const double plastic = v1 * (t - t1) + 0.25 * kG * (t - t1) * (t - t1);  // 0.22 m
  EXPECT_NEAR(summary["ties"]["largest_plastic_elongation_m"].get<double>(), plastic, 0.005 * plastic);
  EXPECT_NEAR(summary["ties"]["peak_tension_by_rod_n"][0].get<double>(), yield_force, 1e-9 * yield_force);
  EXPECT_LT(summary["ties"]["peak_tension_by_rod_n"][1].get<double>(), 1e-3 * yield_force);  // slack
  EXPECT_NEAR(summary["ties"]["yield_force_by_rod_n"][1].get<double>(), 2.35e8 * area, 1e-6);  // mild steel's
  EXPECT_EQ(summary["tie_rods"], 2);
  EXPECT_EQ(summary["ties_yielded"], 1);
  // The rod's work F_y p is in the balance: it closes as the cube falls 0.2 m.
  EXPECT_LT(std::abs(summary["energy_balance_error_relative"].get<double>()), 1e-3);
}

}  // namespace
}  // namespace ishibashi
