// Where the bridge generator puts its stones, against the spec's numbers: spans a pier
// apart, side walls fixed, each course's stones up to one level, the mortar's fracture
// energies on the stone, and clear errors for impossible parameters.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "geometry/bridge.h"
#include "io/model_file.h"

namespace ishibashi {
namespace {

BridgeSpec preset(const char* file) {
  return read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / file).bridge;
}

double highest_z(const BridgeBlock& b) {
  double z = -1e300;
  for (const Vec3& v : b.shape.vertices) z = std::max(z, v.z());
  return z;
}

// Model F: two rings whose springers stand pier_width_m apart, centred on x = 0, between
// fixed side walls.
TEST(BridgeLayout, TwoSpansStandAPierApartBetweenFixedSideWalls) {
  const BridgeSpec spec = preset("nishida_f.toml");
  ASSERT_EQ(spec.spans, 2);
  double left_ring_end = -1e300, right_ring_start = 1e300;
  int side_walls = 0;
  for (const BridgeBlock& b : generate_bridge(spec)) {
    if (b.part == Part::side_wall) {
      ++side_walls;
      EXPECT_TRUE(b.fixed);
    }
    if (b.part != Part::ring) continue;
    double lo = 1e300, hi = -1e300;
    for (const Vec3& v : b.shape.vertices) lo = std::min(lo, v.x()), hi = std::max(hi, v.x());
    if (hi <= 0) left_ring_end = std::max(left_ring_end, hi);
    else right_ring_start = std::min(right_ring_start, lo);
  }
  EXPECT_EQ(side_walls, 2);
  EXPECT_NEAR(left_ring_end, -0.5 * spec.pier_width_m, 1e-9);
  EXPECT_NEAR(right_ring_start, 0.5 * spec.pier_width_m, 1e-9);
}

// Courses are tagged by the level they reach: every wall and fill stone of one course has
// its top at that course's level, the cut stones over the crown's chords included.
TEST(BridgeLayout, AStoneOfACourseReachesThatCoursesLevel) {
  for (const char* file : {"nishida_b.toml", "nishida_f.toml"}) {
    std::map<int, double> top_of_course;
    for (const BridgeBlock& b : generate_bridge(preset(file))) {
      if (b.part != Part::wall && b.part != Part::fill) continue;
      const auto [at, first] = top_of_course.emplace(b.course, highest_z(b));
      if (!first) EXPECT_NEAR(highest_z(b), at->second, 1e-9) << file << ", course " << b.course;
    }
    EXPECT_GT(top_of_course.size(), 5u) << file;
  }
}

// The stone's material carries the mortar: its strength and both fracture energies.
TEST(BridgeLayout, TheStoneCarriesTheMortarsStrengthAndFractureEnergies) {
  BridgeSpec spec;
  spec.mortar_pa = 1e5;
  spec.mortar_tension_fracture_j_m2 = 10;
  spec.mortar_shear_fracture_j_m2 = 20;
  const Model m = compile_bridge(spec, generate_bridge(spec));
  const Material& stone = m.materials[m.material[crown_unit(m)]];
  EXPECT_EQ(stone.tensile_pa, 1e5);
  EXPECT_EQ(stone.cohesion_pa, 1e5);
  EXPECT_EQ(stone.tension_fracture_j_m2, 10);
  EXPECT_EQ(stone.shear_fracture_j_m2, 20);
}

TEST(Bridge, ImpossibleParametersAreClearErrors) {
  using ::testing::HasSubstr;
  auto error = [](const BridgeSpec& s) {
    try {
      generate_bridge(s);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BridgeSpec s;
  s.fill_height_m = 4.0;  // below the crown
  s.length_m = 24.0;
  EXPECT_THAT(error(s), HasSubstr("fill_height_m"));
  s.fill_height_m = 5.8;
  s.length_m = 10.0;  // shorter than the ring
  EXPECT_THAT(error(s), HasSubstr("length_m"));
  s = BridgeSpec{};
  s.ring.rise_m = 7.0;
  EXPECT_THAT(error(s), HasSubstr("rise_m"));
  s = BridgeSpec{};
  s.ring.thickness_m = 0.0;
  EXPECT_THAT(error(s), HasSubstr("thickness_m must be positive"));
  s = BridgeSpec{};
  s.fill_height_m = -1.0;  // a negative height
  EXPECT_THAT(error(s), HasSubstr("fill_height_m and length_m must be >= 0"));
  s = BridgeSpec{};
  s.ring.stone_m = 4.0;  // stones larger than the ring is wide
  EXPECT_THAT(error(s), HasSubstr("stone_m must not exceed the ring width"));
  s = BridgeSpec{};
  s.ground_margin_m = -1.0;
  EXPECT_THAT(error(s), HasSubstr("ground_margin_m must be >= 0"));
  s = BridgeSpec{};  // two spans and no pier between them: the fill's cut crashed
  s.spans = 2;
  s.fill_height_m = 5.8;
  s.length_m = 40.0;
  s.pier_width_m = 0.0;
  EXPECT_THAT(error(s), HasSubstr("pier_width_m (0) must be at least 0.3 stone_m (0.192 m) between spans"));
  s.pier_width_m = 0.001;  // a sliver above it: a 1 kg stone
  EXPECT_THAT(error(s), HasSubstr("pier_width_m (0.001) must be at least"));
  s.pier_width_m = 0.1;  // still under 0.3 stone
  EXPECT_THAT(error(s), HasSubstr("pier_width_m (0.1) must be at least"));
  s.pier_width_m = 0.2;
  EXPECT_EQ(error(s), "no error");
  s = BridgeSpec{};  // stones in millimetres: 10^9 fill blocks, refused before any is made
  s.fill_height_m = 5.8;
  s.length_m = 24.0;
  s.ring.stone_m = 0.004;
  EXPECT_THAT(error(s), HasSubstr("stone_m = 0.004 m cuts the bridge into about"));
  EXPECT_THAT(error(s), HasSubstr("is stone_m in metres?"));
  s = BridgeSpec{};  // soil inside needs a face wall on each side of it
  s.fill_height_m = 5.8;
  s.length_m = 24.0;
  s.backfill = Backfill::soil;
  s.ring.width_m = 1.28;  // two stones across
  EXPECT_THAT(error(s), HasSubstr("soil backfill needs at least 3 stones across the width"));
  s.ring.width_m = 1.92;
  EXPECT_EQ(error(s), "no error");
}

}  // namespace
}  // namespace ishibashi
