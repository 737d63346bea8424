// Capped dashpots (Damping::capped) against closed forms: the cap of a stone
// on a base from its six modes worked out by hand, no change where the step resolves the
// dashpots, and a stack that settles stably at a step the study's dashpots cannot take.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/pipeline.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "scenes.h"
#include "stone_stack.h"

namespace ishibashi {
namespace {

using test::kG;
using test::kStone;

Model stone_on_base(double h, bool capped, int stones = 1) {
  return test::stone_stack(h, capped ? Damping::capped : Damping::study, stones);
}

// The largest damping ratio a mode of angular frequency omega may keep at dt:
// dt = 0.8 * 2/omega (sqrt(1 + z^2) - z) solved for z.
double zeta_max(double omega, double dt) {
  const double x = omega * dt / (2.0 * kDampingCapMargin);
  return std::max(0.0, (1.0 - x * x) / (2.0 * x));
}

// One stone on a base as thick as itself: four corner sub-contacts of area S/4, each with
// k_n = E S/4 / L_z, k_s likewise with G, and m_eq = M/4 (MODEL.md section 3), so
// c = 2 h sqrt(M/4 k) = h sqrt(M k). The six modes of the stone on its corners:
//   bounce z and slide x, y: K = 4 k, zeta = h;
//   rocking about x: K = 4 k_n (L_y/2)^2 + 4 k_s (L_z/2)^2 (the shear springs act at the
//     lever L_z/2 below the centroid), I = M (L_y^2 + L_z^2)/12; about y likewise;
//   twist about z: K = k_s (L_x^2 + L_y^2), I = M (L_x^2 + L_y^2)/12, zeta = sqrt(3) h.
struct Mode {
  double stiffness, damping, mass;
  double omega() const { return std::sqrt(stiffness / mass); }
  double zeta() const { return damping / (2.0 * std::sqrt(stiffness * mass)); }
};

std::vector<Mode> stone_modes(double h) {
  const Material mat = test::stone(h);
  const double shear_modulus = mat.young_pa / (2.0 * (1.0 + mat.poisson));
  const double mass = mat.density_kg_m3 * kStone.prod(), area = kStone.x() * kStone.y() / 4;
  const double kn = mat.young_pa * area / kStone.z(), ks = shear_modulus * area / kStone.z();
  const double cn = h * std::sqrt(mass * kn), cs = h * std::sqrt(mass * ks);
  const double lx2 = 0.25 * kStone.x() * kStone.x(), ly2 = 0.25 * kStone.y() * kStone.y(), lz2 = 0.25 * kStone.z() * kStone.z();
  return {{4 * kn, 4 * cn, mass},
          {4 * ks, 4 * cs, mass},
          {4 * ks, 4 * cs, mass},
          {4 * kn * ly2 + 4 * ks * lz2, 4 * cn * ly2 + 4 * cs * lz2, mass * (ly2 + lz2) / 3},
          {4 * kn * lx2 + 4 * ks * lz2, 4 * cn * lx2 + 4 * cs * lz2, mass * (lx2 + lz2) / 3},
          {4 * ks * (lx2 + ly2), 4 * cs * (lx2 + ly2), mass * (lx2 + ly2) / 3}};
}

TEST(DampingCap, CapOfAStoneOnABaseIsTheClosedForm) {
  const std::vector<Mode> modes = stone_modes(1.0);
  double omega_max = 0;
  for (const Mode& mode : modes) omega_max = std::max(omega_max, mode.omega());
  const double springs_limit = 2.0 / omega_max;
  EXPECT_NEAR(World(stone_on_base(1.0, true), 1e-9).critical_time_step_s(), springs_limit, 1e-9 * springs_limit);
  for (double share : {0.1, 0.2, 0.4}) {
    const double dt = share * springs_limit;
    double expected = 1.0;
    for (const Mode& mode : modes) expected = std::min(expected, zeta_max(mode.omega(), dt) / mode.zeta());
    const World w(stone_on_base(1.0, true), dt);
    EXPECT_NEAR(w.state().damping_scale[1], expected, 1e-9) << "dt " << share << " of the springs' limit";
    EXPECT_EQ(w.state().damping_scale[0], 1.0) << "the fixed base is never capped";
  }
}

// The study's dashpots, block by block: the stone's own limit is the smallest of its six
// modes' 2/omega (sqrt(1 + zeta^2) - zeta), set by the mode that gives it (a rocking mode:
// its corner dashpots act with the corners' levers); the fixed base has none.
TEST(DampingCap, StoneOnABaseLimitIsItsStiffestDampedMode) {
  const std::vector<Mode> modes = stone_modes(1.0);
  double expected = INFINITY;
  int expected_dof = -1;
  for (int j = 0; j < 6; ++j) {
    const double z = modes[j].zeta();
    const double limit = 2.0 / modes[j].omega() * (std::sqrt(1.0 + z * z) - z);
    if (limit < expected) expected = limit, expected_dof = j;
  }
  ASSERT_GE(expected_dof, 3) << "rocking or twist sets the stone's limit";
  const World w(stone_on_base(1.0, false), 1e-9);
  const std::vector<BlockLimit> limits = block_stability_limits(w.model(), w.state(), /*with_damping=*/true);
  ASSERT_EQ(limits.size(), 2u);
  EXPECT_FALSE(std::isfinite(limits[0].dt_s)) << "the fixed base";
  EXPECT_NEAR(limits[1].dt_s, expected, 1e-9 * expected);
  EXPECT_EQ(limits[1].dof, expected_dof);
  int block = -1;
  EXPECT_EQ(stability_limit_s(w.model(), w.state(), true, &block), limits[1].dt_s);
  EXPECT_EQ(block, 1);
}

// Where the step resolves every dashpot, the caps change nothing, to the last bit.
TEST(DampingCap, DashpotsThatTheStepResolvesAreLeftAsSpecified) {
  auto shaken_hash = [](bool capped) {
    WallSpec spec;
    spec.courses = 4;
    spec.stones_per_course = 5;
    const double dt = 0.8 * World(make_wall_model(spec), 1e-9).critical_time_step_s();
    spec.options.damping = capped ? Damping::capped : Damping::study;
    World w(make_wall_model(spec), dt);
    for (double f : w.state().damping_scale) EXPECT_EQ(f, 1.0);
    for (int i = 0; i < 2000; ++i) {
      w.state().velocity[0].x() = 0.3 * std::sin(2 * M_PI * 4.0 * w.state().time_s);
      w.step();
    }
    return w.state_hash();
  };
  EXPECT_EQ(shaken_hash(true), shaken_hash(false));
}

// Four stones stacked on a base with h = 1, at 0.4 of the springs' limit: more than the
// study's dashpots allow (the World refuses the step), but with caps the stack settles
// under its weight: the base carries the weight of the four stones, nothing moves any
// more, and the energy balance closes.
TEST(DampingCap, StackSettlesAtAStepTheStudyDashpotsCannotTake) {
  const double dt = 0.4 * World(stone_on_base(1.0, true, 4), 1e-9).critical_time_step_s();
  EXPECT_THROW(World(stone_on_base(1.0, false, 4), dt), ModelError);
  World w(stone_on_base(1.0, true, 4), dt);
  EXPECT_LT(*std::min_element(w.state().damping_scale.begin(), w.state().damping_scale.end()), 1.0);
  test::expect_stack_settles(w, 4);
}

}  // namespace
}  // namespace ishibashi
