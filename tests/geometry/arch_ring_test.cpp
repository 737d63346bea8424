// The arch ring generator: sound blocks, the design volume, bad parameters, and a dry
// ring (Nishida model A) that stands under its own weight.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "engine/mass_properties.h"
#include "engine/world.h"
#include "geometry/arch_ring.h"
#include "geometry/bridge.h"
#include "io/model_file.h"

namespace ishibashi {
namespace {

// The ring as an engine Model (springing stones fixed).
Model make_arch_ring_model(const ArchRingSpec& s) {
  ModelBuilder builder;
  const int stone = builder.add_material(s.stone.name.empty() ? nishida_stone() : s.stone);
  for (const Voussoir& v : make_arch_ring(s))
    builder.add_block(v.shape.vertices, v.shape.faces, stone, v.fixed ? Motion::fixed : Motion::free,
                      "ring-" + std::to_string(v.ring_index) + "-" + std::to_string(v.course));
  return builder.build();
}


TEST(ArchRing, VolumeEqualsTheAnnularSectorMinusChordLosses) {
  // Voussoirs have plane intrados and extrados faces, so the ring is the annular sector
  // less the circular segments cut off by each chord: with n stones over an embrace of
  // 2 alpha, volume = width * n/2 (R_out^2 - R_in^2) sin(2 alpha / n).
  ArchRingSpec spec;
  const auto ring = make_arch_ring(spec);
  double volume = 0;
  int along = 0;
  for (const Voussoir& v : ring) {
    volume += polyhedron_mass_properties(v.shape.vertices, v.shape.faces).volume_m3;
    along = std::max(along, v.ring_index + 1);
  }
  const double half = spec.span_m / 2, r_in = (half * half + spec.rise_m * spec.rise_m) / (2 * spec.rise_m);
  const double r_out = r_in + spec.thickness_m, alpha = std::asin(half / r_in);
  const double expected = spec.width_m * along / 2.0 * (r_out * r_out - r_in * r_in) * std::sin(2 * alpha / along);
  EXPECT_NEAR(volume, expected, 1e-9 * expected);
  EXPECT_EQ(ring.size(), static_cast<std::size_t>(along * 5));
}

// Without a voussoir count, the ring has the nearest whole number of stones of stone_m
// along its arc at mid-thickness, and across its width: 3.0 m / 0.64 m = 4.7, five across.
TEST(ArchRing, StonesAlongAndAcrossAreTheNearestWholeNumbersOfStoneLengths) {
  ArchRingSpec spec;
  spec.width_m = 3.0;
  const auto ring = make_arch_ring(spec);
  const double half = spec.span_m / 2, r_in = (half * half + spec.rise_m * spec.rise_m) / (2 * spec.rise_m);
  const long along = std::lround(2 * std::asin(half / r_in) * (r_in + spec.thickness_m / 2) / spec.stone_m);  // 27
  int most_along = 0;
  for (const Voussoir& v : ring) most_along = std::max(most_along, v.ring_index + 1);
  EXPECT_EQ(most_along, along);
  EXPECT_EQ(ring.size(), static_cast<std::size_t>(along * 5));
}

TEST(ArchRing, ImpossibleParametersAreClearErrors) {
  using ::testing::HasSubstr;
  auto error = [](ArchRingSpec s) {
    try {
      make_arch_ring(s);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ArchRingSpec s;
  s.rise_m = 6.0;  // above half of 11.36
  EXPECT_THAT(error(s), HasSubstr("rise_m"));
  s = ArchRingSpec{};
  s.thickness_m = -0.1;
  EXPECT_THAT(error(s), HasSubstr("thickness_m must be positive"));
  s = ArchRingSpec{};
  s.stone_m = 4.0;
  EXPECT_THAT(error(s), HasSubstr("stone_m"));
  s = ArchRingSpec{};
  s.voussoirs = 100000;  // slivers 0.16 mm along the intrados
  EXPECT_THAT(error(s), HasSubstr("voussoirs = 100000 makes each 0.000161 m along the intrados, less than a tenth of stone_m"));
  s.voussoirs = 33;  // the study's model A
  EXPECT_EQ(error(s), "no error");
}

TEST(ArchRing, DryModelAStandsUnderGravity) {
  // The preset of Nishida model A (33 voussoirs, dry joints, fixed springers) on its
  // ground, under gravity alone.
  const ModelFile file = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / "nishida_a.toml");
  const Model m = compile_bridge(file.bridge, generate_bridge(file.bridge));
  const double dt = 0.8 * World(m, 1e-7).critical_time_step_s();
  World w(m, dt);
  State& s = w.state();
  auto largest_displacement = [&] {
    double d = 0;
    for (int b = 0; b < m.block_count; ++b) d = std::max(d, (s.position[b] - m.initial_position[b]).norm());
    return d;
  };
  w.run(std::lround(0.3 / dt));  // settled (critically damped joints)
  const double settled = largest_displacement();
  EXPECT_LT(settled, 1e-3);
  EXPECT_GT(settled, 1e-5);  // it did deflect under its weight (the crown drops)
  w.run(std::lround(1.0 / dt));  // and over one more second no block moves further
  EXPECT_LT(largest_displacement() - settled, 1e-5);
  EXPECT_LT(s.energy.kinetic_j, 1e-3);
}

TEST(ArchRing, RunningBondRingAlsoStands) {
  ArchRingSpec spec;
  spec.bond = Bond::running;
  const Model m = make_arch_ring_model(spec);
  World w(m, 1e-5);
  w.run(30000);
  double d = 0;
  for (int b = 0; b < m.block_count; ++b) d = std::max(d, (w.state().position[b] - m.initial_position[b]).norm());
  EXPECT_LT(d, 1e-3);
  EXPECT_LT(w.state().energy.kinetic_j, 1e-3);
}

}  // namespace
}  // namespace ishibashi
