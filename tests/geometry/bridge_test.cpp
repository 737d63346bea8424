// The bridge generator and its presets: counts near the study's, exact design volume,
// CGAL validation (sound blocks, no overlaps, shared faces), clear errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include "engine/world.h"
#include "geometry/bridge.h"
#include "geometry/shapes.h"
#include "geometry/validate.h"
#include "io/model_file.h"
#include "scenes.h"

namespace ishibashi {
namespace {

std::vector<Polyhedron> shapes_of(const std::vector<BridgeBlock>& blocks, bool with_ground) {
  std::vector<Polyhedron> out;
  for (const BridgeBlock& b : blocks)
    if (with_ground || b.part != Part::ground) out.push_back(b.shape);
  return out;
}

struct Preset {
  const char* file;
  int study_count;
};

class Presets : public ::testing::TestWithParam<Preset> {};

TEST_P(Presets, CountVolumeAndValidation) {
  const Preset p = GetParam();
  const ModelFile file = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / p.file);
  const std::vector<BridgeBlock> blocks = generate_bridge(file.bridge);
  const int count = static_cast<int>(blocks.size()) - 1;  // the ground slab is ours, not the study's
  EXPECT_NEAR(count, p.study_count, 0.10 * p.study_count) << p.file;

  // The blocks fill the design outline exactly: no gaps, no overlaps (CGAL).
  const ValidationReport r = validate_blocks(shapes_of(blocks, false), {});
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors.front());
  EXPECT_EQ(r.overlapping_pairs, 0);
  EXPECT_NEAR(r.volume_m3, design_volume_m3(file.bridge), 1e-9 * r.volume_m3);
  EXPECT_GT(r.shared_faces, count);  // a connected assembly: more joints than blocks

  // Every fill stone stands on something and none is a sliver.
  for (const BridgeBlock& b : blocks) {
    double lo = 1e9, hi = -1e9;
    for (const Vec3& v : b.shape.vertices) {
      lo = std::min(lo, v.z());
      hi = std::max(hi, v.z());
    }
    EXPECT_GT(hi - lo, 0.29 * file.bridge.ring.stone_m) << part_name(b.part);
  }
}

INSTANTIATE_TEST_SUITE_P(Nishida, Presets,
                         ::testing::Values(Preset{"nishida_a.toml", 165}, Preset{"nishida_b.toml", 1586},
                                           Preset{"nishida_c.toml", 1588}, Preset{"nishida_d.toml", 1448},
                                           Preset{"nishida_e.toml", 1450}, Preset{"nishida_f.toml", 2043}),
                         [](const ::testing::TestParamInfo<Preset>& info) {
                           return std::filesystem::path(info.param.file).stem().string();
                         });

// The units an analysis monitors are found by where they are, not by their numbers:
// numbered the other way round, each preset's crown unit and the unit beside it are the
// same stones (a symmetric ring has mirror units at the crown's height; a tie between
// them must not go to whichever the generator numbered first).
TEST_P(Presets, MonitoredUnitsDoNotDependOnTheNumbering) {
  const ModelFile file = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / GetParam().file);
  std::vector<BridgeBlock> blocks = generate_bridge(file.bridge);
  const Model m = compile_bridge(file.bridge, blocks);
  std::reverse(blocks.begin(), blocks.end() - 1);  // the ground slab stays last
  const Model reversed = compile_bridge(file.bridge, blocks);
  for (auto unit : {crown_unit, face_unit_beside_crown}) {
    ASSERT_GE(unit(m), 0);
    EXPECT_EQ(m.initial_position[unit(m)], reversed.initial_position[unit(reversed)]);
  }
  // The crown unit is the middle one across the width; the unit beside it is on the +y face,
  // a voussoir along the arc: off both symmetry planes.
  const Vec3 crown = m.initial_position[crown_unit(m)], beside = m.initial_position[face_unit_beside_crown(m)];
  double face_y = -1e300;
  for (int b = 0; b < m.block_count; ++b)
    if (m.block_tag[b].part == static_cast<int>(Part::ring)) face_y = std::max(face_y, m.initial_position[b].y());
  EXPECT_LE(std::abs(crown.y()), 0.5 * file.bridge.ring.stone_m);
  EXPECT_NEAR(beside.y(), face_y, 1e-9);
  EXPECT_GT(std::abs(beside.x() - crown.x()), 0.5 * file.bridge.ring.stone_m);
}

// Numbered the other way round, each preset's bridge has the same joints: as many
// sub-contacts, the same total area, and the same stable step (whose limit each joint's
// normal and points set; an edge contact's normal once went with which stone was a).
TEST_P(Presets, ContactsAndStableStepDoNotDependOnTheNumbering) {
  const ModelFile file = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / GetParam().file);
  std::vector<BridgeBlock> blocks = generate_bridge(file.bridge);
  auto found = [&] {
    const Model m = compile_bridge(file.bridge, blocks);
    const State s = test::contacts_found(m);
    double area = 0;
    for (std::size_t i = 0; i < s.contacts.size(); ++i) area += s.contacts.area_m2[i];
    return std::tuple(s.contacts.size(), area, stability_limit_s(m, s, true, nullptr));
  };
  const auto [count, area, limit] = found();
  std::reverse(blocks.begin(), blocks.end() - 1);  // the ground slab stays last
  const auto [reversed_count, reversed_area, reversed_limit] = found();
  EXPECT_EQ(count, reversed_count);
  EXPECT_NEAR(area, reversed_area, 1e-9 * area);
  EXPECT_NEAR(limit, reversed_limit, 1e-9 * limit);
}

TEST(Bridge, SoilBackfillHasStoneFaceWallsAndSoilInside) {
  BridgeSpec s;
  s.fill_height_m = 5.8;
  s.length_m = 24.0;
  s.backfill = Backfill::soil;
  int walls = 0, soil = 0, fill = 0;
  for (const BridgeBlock& b : generate_bridge(s)) {
    walls += b.part == Part::wall;
    soil += b.part == Part::soil;
    fill += b.part == Part::fill;
  }
  EXPECT_EQ(fill, 0);
  EXPECT_EQ(soil * 2, walls * 3);  // 5 across: 2 face walls, 3 soil units
  const Model m = compile_bridge(s, generate_bridge(s));
  EXPECT_EQ(m.materials[1].name, "soil");
}

// The ground's material: stone by default, the soil with ground = soil (MODEL.md section
// 4); a stone standing on a soil ground meets it with the soil's E in K_n (the harmonic
// mean of MODEL.md section 3) and the soil's friction angle.
TEST(Bridge, GroundOfSoilGivesItsJointsTheSoilsStiffnessAndFriction) {
  BridgeSpec s;
  s.fill_height_m = 5.8;
  s.length_m = 24.0;
  for (GroundMaterial ground : {GroundMaterial::stone, GroundMaterial::soil}) {
    s.ground = ground;
    const Model m = compile_bridge(s, generate_bridge(s));
    int ground_block = -1, wall_block = -1;
    for (int b = 0; b < m.block_count; ++b) {
      if (m.block_tag[b].part == static_cast<int>(Part::ground)) ground_block = b;
      if (m.block_tag[b].part == static_cast<int>(Part::wall) && wall_block < 0) wall_block = b;
    }
    ASSERT_GE(ground_block, 0);
    ASSERT_GE(wall_block, 0);
    const Material& g = m.materials[m.material[ground_block]];
    EXPECT_EQ(g.name, ground == GroundMaterial::soil ? "soil" : "stone");
    EXPECT_EQ(g.young_pa, ground == GroundMaterial::soil ? 1.9e8 : 1.4039e10);
    const PairLaw& law = m.law(m.material[ground_block], m.material[wall_block]);
    EXPECT_NEAR(law.tan_friction, std::tan((ground == GroundMaterial::soil ? 30.0 : 33.23) * M_PI / 180), 1e-12);
    EXPECT_EQ(law.tensile_pa, 0.0);  // never reinforced
  }
}

// The ground reaches ground_margin_m beyond the bridge's walls on every side; by default
// four times the bridge's height, beyond the sqrt(6) H = 2.4 H that a wall toppling out
// of plane throws its stones.
TEST(Bridge, GroundReachesItsMarginBeyondTheBridge) {
  const ModelFile file = read_model_file(std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "models" / "nishida_b.toml");
  auto reach = [](const BridgeSpec& spec) {
    Vec3 bridge_hi(-1e9, -1e9, -1e9), ground_hi = bridge_hi;
    for (const BridgeBlock& b : generate_bridge(spec)) {
      Vec3& hi = b.part == Part::ground ? ground_hi : bridge_hi;
      for (const Vec3& v : b.shape.vertices) hi = hi.cwiseMax(v);
    }
    return std::pair<Vec3, double>(ground_hi - bridge_hi, bridge_hi.z());  // Vec3: not an expression of these locals
  };
  BridgeSpec spec = file.bridge;
  const auto [beyond, height] = reach(spec);
  EXPECT_NEAR(height, spec.fill_height_m, 1e-9);
  EXPECT_NEAR(beyond.x(), 4 * height, 1e-9);  // along the bridge, beyond the side walls
  EXPECT_NEAR(beyond.y(), 4 * height, 1e-9);  // across it, beyond the wall faces
  spec.ground_margin_m = 30.0;
  EXPECT_NEAR(reach(spec).first.y(), 30.0, 1e-9);
}

// fixed_bottom_course fixes exactly the walls, fill and soil units that stand on the
// ground (lowest vertex at z = 0), as the springers are; without it they are free.
TEST(Bridge, FixedBottomCourseFixesWhatStandsOnTheGround) {
  for (Backfill backfill : {Backfill::stone, Backfill::soil})
    for (bool fixed_bottom : {false, true}) {
      BridgeSpec s;
      s.fill_height_m = 5.8;
      s.length_m = 24.0;
      s.backfill = backfill;
      s.fixed_bottom_course = fixed_bottom;
      int on_ground = 0, fixed_fill = 0;
      for (const BridgeBlock& b : generate_bridge(s)) {
        if (b.part != Part::wall && b.part != Part::fill && b.part != Part::soil) continue;
        double lowest = 1e9;
        for (const Vec3& v : b.shape.vertices) lowest = std::min(lowest, v.z());
        on_ground += lowest < 1e-9;
        fixed_fill += b.fixed;
        EXPECT_EQ(b.fixed, fixed_bottom && lowest < 1e-9) << part_name(b.part) << " at z " << lowest;
      }
      EXPECT_GT(on_ground, 2 * 5) << "a course of stones five across on each side of the ring";
      EXPECT_EQ(fixed_fill, fixed_bottom ? on_ground : 0);
    }
}

// mortar_parts: a joint carries the mortar when both its blocks belong to a listed part.
// Counted on the bonded sub-contacts of the joints in contact at the start, by the parts
// their blocks belong to: the ring grouted alone bonds ring to ring and nothing else; the
// walls and fill repointed bond no joint of the ring; every stone part (the default, or
// listed in full) bonds the same sub-contacts with one stone material, as before the option.
TEST(Bridge, MortarPartsBondOnlyTheJointsBetweenListedParts) {
  BridgeSpec s;
  s.fill_height_m = 5.8;
  s.length_m = 24.0;
  s.mortar_pa = 2e5;
  const std::vector<BridgeBlock> blocks = generate_bridge(s);
  using PartPair = std::pair<Part, Part>;
  auto bonded_by_parts = [&](std::vector<Part> parts, int* materials) {
    s.mortar_parts = std::move(parts);
    World world(compile_bridge(s, blocks), 1e-8);
    world.form_bonds();
    const Model& m = world.model();
    const State& st = world.state();
    *materials = static_cast<int>(m.materials.size());
    std::map<PartPair, int> count;
    for (const Pair& pair : st.pairs)
      for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
        if (!(st.contacts.flags[i] & SubContactFlag::bonded)) continue;
        Part a = static_cast<Part>(m.block_tag[pair.a].part), b = static_cast<Part>(m.block_tag[pair.b].part);
        count[{std::min(a, b), std::max(a, b)}]++;
      }
    return count;
  };
  int materials = 0;
  const auto every = bonded_by_parts({}, &materials);
  EXPECT_EQ(materials, 2);  // stone, soil: as before mortar_parts
  EXPECT_GT(every.at({Part::ring, Part::ring}), 0);
  EXPECT_GT(every.at({Part::wall, Part::wall}), 0);
  EXPECT_GT(every.at({Part::ring, Part::fill}), 0);
  for (const auto& [parts, n] : every) EXPECT_NE(parts.first, Part::ground) << "the soil ground never carries mortar";
  EXPECT_EQ(bonded_by_parts({Part::ring, Part::wall, Part::fill}, &materials), every);
  EXPECT_EQ(materials, 2);

  const auto ring = bonded_by_parts({Part::ring}, &materials);
  EXPECT_EQ(materials, 3);  // and stone without the bond
  ASSERT_EQ(ring.size(), 1u);
  EXPECT_EQ(ring.at({Part::ring, Part::ring}), every.at({Part::ring, Part::ring}));

  const auto walls_and_fill = bonded_by_parts({Part::wall, Part::fill}, &materials);
  for (const auto& [parts, n] : walls_and_fill) {
    EXPECT_NE(parts.first, Part::ring);
    EXPECT_EQ(n, every.at(parts));
  }
  EXPECT_EQ(walls_and_fill.at({Part::wall, Part::wall}), every.at({Part::wall, Part::wall}));
  EXPECT_FALSE(walls_and_fill.count({Part::ring, Part::fill}));
}

// A stone hanging under a fixed one by its mortar joint (bonded from the start): held where
// both stones' parts are listed (the bond's 200 kPa against the stone's weight over its
// face, 18 kPa), in free fall, g t^2 / 2, where the hanging stone's part is not.
TEST(Bridge, AStoneHangsByItsMortarOnlyWhereBothPartsAreListed) {
  BridgeSpec s;
  s.mortar_pa = 2e5;
  const std::vector<BridgeBlock> blocks{{make_box({0, 0, 1.5}, {1, 1, 1}), Part::ring, 0, true},
                                        {make_box({0, 0, 0.5}, {1, 1, 1}), Part::wall, 0, false}};
  for (const bool held : {true, false}) {
    s.mortar_parts = held ? std::vector<Part>{Part::ring, Part::wall} : std::vector<Part>{Part::ring};
    World probe(compile_bridge(s, blocks), 1e-9);
    const double dt = 0.5 * probe.critical_time_step_s();
    World world(compile_bridge(s, blocks), dt);
    const long steps = std::lround(0.1 / dt);
    world.run(steps);
    const double t = steps * dt, drop = 0.5 - world.state().position[1].z();
    if (held)
      EXPECT_LT(std::abs(drop), 1e-5) << "held by the bond";
    else
      EXPECT_NEAR(drop, 0.5 * 9.81 * t * t, 1e-3 * 0.5 * 9.81 * t * t) << "falls free";
  }
}

// A listed part the bridge has no stone block of is an error, not mortar silently nowhere.
TEST(Bridge, AMortarPartTheBridgeLacksIsAnError) {
  using ::testing::HasSubstr;
  BridgeSpec s;  // the ring alone
  s.mortar_pa = 2e5;
  s.mortar_parts = {Part::ring, Part::wall};
  try {
    compile_bridge(s, generate_bridge(s));
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_THAT(e.what(), HasSubstr("lists \"wall\", but the bridge has no stone block of that part"));
  }
  s.mortar_pa = 0;  // dry: the list says nothing
  EXPECT_NO_THROW(compile_bridge(s, generate_bridge(s)));
}

// The Python readers of the outputs (analysis/report/run_outputs.py, PART) name every part
// number of the cell array "part" as the generator does, and no other.
TEST(BridgeParts, PythonReadersKnowEveryPart) {
  using ::testing::HasSubstr;
  std::ifstream file(std::string(ISHIBASHI_SOURCE_DIR) + "/analysis/report/run_outputs.py");
  std::string line;
  while (std::getline(file, line) && line.rfind("PART = {", 0) != 0) {
  }
  ASSERT_EQ(line.rfind("PART = {", 0), 0u) << "no PART = {...} line";
  int entries = 0;
  for (int p = 0; p <= static_cast<int>(Part::imported); ++p) {
    std::string name = part_name(static_cast<Part>(p));
    std::replace(name.begin(), name.end(), ' ', '_');
    EXPECT_THAT(line, HasSubstr("\"" + name + "\": " + std::to_string(p))) << name;
    ++entries;
  }
  EXPECT_EQ(std::count(line.begin(), line.end(), ':'), entries) << line;
}

}  // namespace
}  // namespace ishibashi
