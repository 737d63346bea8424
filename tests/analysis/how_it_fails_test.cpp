// summary.json's how_it_fails against the pseudo-static tipping of a rigid block: a block of
// width b and height h on a pedestal, under a constant horizontal ground acceleration a,
// stands while a < g b / h and tips over the edge away from the acceleration (the inertial
// force -m a in the ground's frame) once a > g b / h, falling off the pedestal to the slab.
// The ring's hinges against the classical limit state of a semicircular arch under its own
// weight. And the sentence's wording from a summary's parts, directions and hinges.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <csignal>
#include <fstream>
#include <numbers>
#include <nlohmann/json.hpp>

#include "analysis/run/how_it_fails.h"
#include "command_line.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "scenes.h"

namespace ishibashi {
namespace {

namespace fs = std::filesystem;

// Axis-aligned boxes, {lower corner, upper corner} each, as one OFF file (a closed
// component a block; faces wound outward).
std::string boxes_off(const std::vector<std::pair<Vec3, Vec3>>& boxes) {
  std::ostringstream off;
  off << "OFF\n" << 8 * boxes.size() << ' ' << 6 * boxes.size() << " 0\n";
  for (const auto& [lo, hi] : boxes)
    for (int k = 0; k < 8; ++k)
      off << ((k & 1) ? hi.x() : lo.x()) << ' ' << ((k & 2) ? hi.y() : lo.y()) << ' ' << ((k & 4) ? hi.z() : lo.z()) << '\n';
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const std::size_t o = 8 * i;
    for (const auto& face : {std::array{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
      off << "4 " << o + face[0] << ' ' << o + face[1] << ' ' << o + face[2] << ' ' << o + face[3] << '\n';
  }
  return off.str();
}

// A 0.2 x 0.2 x 0.8 m block (b / h = 0.25) on a 0.4 x 0.4 x 1 m pedestal over a 4 x 4 m slab,
// pedestal and slab moving with the ground; a ground acceleration of `g_share` g along
// `axis` (x or y), ramped up over 0.1 s and then held for `held_s`. Returns the scenario file.
fs::path tip_scenario(const std::string& name, char axis, double g_share, double held_s = 2.0) {
  const fs::path dir = fs::temp_directory_path() / ("ishibashi_tip_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "ground.off") << boxes_off({{{-2, -2, -0.2}, {2, 2, 0}}, {{-0.2, -0.2, 0}, {0.2, 0.2, 1.0}}});
  std::ofstream(dir / "block.off") << boxes_off({{{-0.1, -0.1, 1.0}, {0.1, 0.1, 1.8}}});
  std::ofstream(dir / "model.toml") << "[model]\nname = \"block on a pedestal\"\n[import]\nfiles = [\"block.off\"]\n"
                                    << "fixed_files = [\"ground.off\"]\n";
  std::ofstream record(dir / "pull.txt");
  for (int k = 0; k <= 10 + std::lround(100 * held_s); ++k) record << 0.01 * k << ' ' << g_share * std::min(1.0, k / 10.0) << '\n';
  record.close();
  std::ofstream(dir / "shake.toml") << "[model]\nfile = \"model.toml\"\n[run]\nsettle_max_s = 0.3\noutput_interval_s = 0.02\n"
                                    << "[ground_motion]\nbaseline_correction = false\n"  // the pull is the record
                                    << axis << " = { file = \"pull.txt\", format = \"columns\", unit = \"g\" }\n";
  return dir / "shake.toml";
}

const std::string kRun = test::program() + " run --threads 1 --no-report ";

// The scenario's run into `out`; returns its summary.json.
nlohmann::json run(const fs::path& scenario, const fs::path& out, const std::string& options = "") {
  int status = 0;
  const std::string log = test::run_command(kRun + scenario.string() + options + " --out " + out.string(), &status);
  EXPECT_EQ(status, 0) << log;
  return nlohmann::json::parse(test::text_of(out / "summary.json"));
}

// At a quarter of the step: the block's impact on the slab (about 4.5 m/s, a corner first)
// is re-clipped at each step, and the re-clips make 0.7 % of the energy exchanged (2.9 % at
// the whole step, 1.4 % at half: halving with dt; README, "Energy"), booked beside the
// balance, which closes within 0.01 %.
nlohmann::json tip(const std::string& name, char axis, double g_share) {
  const fs::path scenario = tip_scenario(name, axis, g_share);
  return run(scenario, scenario.parent_path() / "out", " --dt-factor 0.25");
}

TEST(HowItFails, ABlockTipsAwayFromTheGroundsPullOnceItExceedsWidthOverHeight) {
  const nlohmann::json stands = tip("stands", 'y', 0.225);  // 0.9 of g b / h
  EXPECT_EQ(stands["fallen_stones"], 0);
  EXPECT_EQ(stands["how_it_fails"]["text"], "no stone fell");
  EXPECT_TRUE(stands["how_it_fails"]["parts"].empty());
  EXPECT_EQ(stands["failure_mode"], "no stone fell");

  for (const auto& [axis, pull, toward, across] : {std::tuple{'y', 0.30, "-y", true}, std::tuple{'y', -0.35, "+y", true},
                                                   std::tuple{'x', 0.35, "-x", false}}) {
    const std::string name = std::string(1, axis) + (pull > 0 ? "_plus" : "_minus");
    const nlohmann::json tips = tip(name, axis, pull);  // 1.2 and 1.4 times g b / h
    ASSERT_EQ(tips["fallen_stones"], 1) << name;
    EXPECT_LT(std::abs(tips["energy_balance_error_relative"].get<double>()), 1e-3) << name;
    EXPECT_GT(tips["energy_reclip_relative"].get<double>(), 2e-3) << name;  // the corner's impact's re-clips
    const auto& how = tips["how_it_fails"];
    EXPECT_EQ(how["toward"][toward], 1) << name << how.dump();
    ASSERT_EQ(how["parts"].size(), 1u);
    EXPECT_EQ(how["parts"][0]["part"], "imported");
    EXPECT_EQ(how["parts"][0]["sides"]["middle"], 1);  // the block stood on the pedestal's middle
    // Tipping from rest takes a while, then a fall of about a metre: within the 2 s held.
    const double fell_s = how["parts"][0]["first_fall_s"].get<double>();
    EXPECT_GT(fell_s, 0.2) << name;
    EXPECT_LT(fell_s, 2.1) << name;
    EXPECT_EQ(tips["failure_mode"], across ? "imported first (across)" : "imported first (along)") << name;
    const std::string text = how["text"].get<std::string>();
    EXPECT_NE(text.find(across ? "; it fell across the bridge (out of plane, 1 toward " + std::string(toward)
                               : "; it fell along the span (in plane, 1 toward " + std::string(toward)),
              std::string::npos)
        << text;
  }
}

// FallRecord on a bridge's parts, its stones moved by hand between two frames: the parts in
// the order their first stones fell (not the parts' order), each fall's time in seconds of
// shaking, its side by where the stone stood, its direction relative to the ground.
TEST(HowItFails, PartsComeInTheOrderTheyFellWithTheirSidesAndDirections) {
  const Polyhedron slab = make_box(Vec3(0, 0, -0.25), Vec3(8, 8, 0.5));
  const Polyhedron ring = make_box(Vec3(0, 0, 2), Vec3(0.4, 2, 0.4)), fill = make_box(Vec3(1, 0.1, 2), Vec3(0.4, 0.4, 0.4));
  const Polyhedron wall_minus = make_box(Vec3(0, -0.8, 3), Vec3(0.4, 0.4, 0.4)), wall_plus = make_box(Vec3(0, 0.8, 3), Vec3(0.4, 0.4, 0.4));
  Model m = test::stones_model({{&slab, Motion::fixed}, {&ring, Motion::free}, {&fill, Motion::free}, {&wall_minus, Motion::free},
                                {&wall_plus, Motion::free}});
  for (const auto& [b, part] : {std::pair{0, Part::ground}, {1, Part::ring}, {2, Part::fill}, {3, Part::wall}, {4, Part::wall}})
    m.block_tag[b].part = static_cast<int>(part);
  State s = make_initial_state(m);
  FallRecord falls(m.block_count);
  const double settled_s = 0.2;
  s.time_s = 1.0;  // the +y wall's stone falls across, the ground displaced 0.2 m along +y
  s.position[4] += Vec3(0.1, 0.5, -2.0);
  falls.note(m, s, Vec3(0, 0.2, 0));
  s.time_s = 1.5;  // then the ring's, along -x; the fill stone sinks less than its size: standing
  s.position[1] += Vec3(-0.6, 0.1, -1.5);
  s.position[2] += Vec3(0, 0, -0.3);
  falls.note(m, s, Vec3(0, 0.2, 0));
  const nlohmann::ordered_json how = how_it_fails(m, falls, RingHinges(m, Joints{}), settled_s);
  ASSERT_EQ(how["parts"].size(), 2u) << how.dump();
  EXPECT_EQ(how["parts"][0]["part"], "wall");
  EXPECT_NEAR(how["parts"][0]["first_fall_s"].get<double>(), 0.8, 1e-12);
  EXPECT_EQ(how["parts"][0]["sides"]["+y"], 1);
  EXPECT_EQ(how["parts"][1]["part"], "ring");
  EXPECT_NEAR(how["parts"][1]["first_fall_s"].get<double>(), 1.3, 1e-12);
  EXPECT_EQ(how["parts"][1]["sides"]["middle"], 1);
  EXPECT_EQ(how["toward"]["+y"], 1);
  EXPECT_EQ(how["toward"]["-x"], 1);
  EXPECT_EQ(how["toward"]["+x"], 0);
  EXPECT_EQ(how["text"], how_it_fails_text(how));
  EXPECT_EQ(failure_mode_of(how), "wall first (both ways)");  // one across, one along: neither two thirds
}

// A run killed after its block fell, and resumed from its last checkpoint, says when and which
// way the block fell as the run never stopped does: the checkpoint keeps the falls noted so far.
TEST(HowItFails, ARunResumedAfterTheFallKeepsItsTimeAndWay) {
  const fs::path scenario = tip_scenario("resumed", 'y', 0.35, 8.0);  // seconds of run after the fall
  const nlohmann::json whole = run(scenario, scenario.parent_path() / "whole");
  ASSERT_EQ(whole["fallen_stones"], 1);
  const fs::path killed = scenario.parent_path() / "killed";
  int status = 0;
  // Killed 0.1 s after the summary.json of a frame (written at each) first counts the fallen
  // block, checkpoints every 0.02 s of simulated time: the resume starts after the fall's frame.
  test::run_command("bash -c '" + kRun + scenario.string() + " --checkpoint-every 0.02 --out " + killed.string() +
                        " > /dev/null & run=$!; until grep -qs fallen_stones.:.1, " + (killed / "summary.json").string() +
                        " || ! kill -0 $run 2> /dev/null; do sleep 0.01; done; sleep 0.1; kill -KILL $run; wait $run'",
                    &status);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGKILL) << "the run ended before it was killed: " << status;
  const std::string resumed = test::run_command(kRun + "--resume " + killed.string(), &status);
  ASSERT_EQ(status, 0) << resumed;
  const nlohmann::json after = nlohmann::json::parse(test::text_of(killed / "summary.json"));
  EXPECT_EQ(after["state_hash"], whole["state_hash"]);
  EXPECT_EQ(after["how_it_fails"], whole["how_it_fails"]);
}

// A semicircular arch of 36 voussoirs (5 degrees each) on radial joints, two stones across its
// 1 m width (stacked), centre-line radius 5 m, thickness t, tagged as a bridge's ring: the
// voussoirs at positions 1 .. 36 along the arc from the -x springing, on two fixed springer
// stones (positions 0 and 37) on a fixed base. Friction 60 degrees: nothing slides. Under its
// own weight for up to 4 s, the hinges noted every 0.05 s (a run's frames) until the crown
// dropped 0.1 m, the mechanism formed.
RingHinges arch_hinges(double t_over_r) {
  const double radius = 5.0, t = t_over_r * radius, inner = radius - t / 2, outer = radius + t / 2;
  const int count = 36;
  ModelBuilder b;
  const int mat = b.add_material(test::stone(1.0, 60.0));
  const Polyhedron base = make_box(Vec3(0, 0, -0.45), Vec3(3 * radius, 2.0, 0.5));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base", {static_cast<int>(Part::ground), 0});
  const int ring = static_cast<int>(Part::ring);
  for (const auto& [x, position] : {std::pair{-radius, 0}, std::pair{radius, count + 1}}) {
    const Polyhedron springer = make_box(Vec3(x, 0, -0.1), Vec3(t, 1.0, 0.2));
    b.add_block(springer.vertices, springer.faces, mat, Motion::fixed, "springer", {ring, position});
  }
  for (int k = 0; k < count; ++k) {
    const double a0 = std::numbers::pi * (1 - double(k) / count), a1 = std::numbers::pi * (1 - double(k + 1) / count);
    const std::vector<Vec3> polygon{{inner * std::cos(a1), 0, inner * std::sin(a1)},
                                    {outer * std::cos(a1), 0, outer * std::sin(a1)},
                                    {outer * std::cos(a0), 0, outer * std::sin(a0)},
                                    {inner * std::cos(a0), 0, inner * std::sin(a0)}};
    for (double y0 : {-0.5, 0.0}) {
      const Polyhedron v = make_prism_xz(polygon, y0, y0 + 0.5);
      b.add_block(v.vertices, v.faces, mat, Motion::free, "voussoir", {ring, k + 1});
    }
  }
  const Model m = b.build({});
  World w(m, 1e-5);
  const State& s = w.state();
  Joints joints = find_original_joints(s);
  RingHinges hinges(m, joints);
  const int crown = 3 + count;  // a voussoir beside the crown joint
  const double z0 = s.position[crown].z();
  while (s.time_s < 4.0 && z0 - s.position[crown].z() < 0.1) {
    w.run(5000);
    measure_joints(s, JointThresholds{}, joints);
    bool ring_fell = false;
    for (int k = 3; k < m.block_count; ++k) ring_fell |= is_fallen(m, s, k);
    hinges.note(joints, s.time_s, ring_fell);
  }
  return hinges;
}

// Heyman's limit state: a semicircular arch needs t/R = 0.1075 (Milankovitch), and one thinner
// collapses on five hinges, at the crown, at 54-59 degrees from it on both sides (the
// haunches) and at the springings. The record finds the sections across the width and the
// angles from the joints' directions, with the -x side negative.
TEST(HowItFails, TheRingHingesOfASemicircularArchAreHeymansFive) {
  const nlohmann::ordered_json stands = arch_hinges(0.12).summary(0.0);
  EXPECT_EQ(stands["sections"], 37);  // between the 38 stones along the arc
  EXPECT_EQ(stands["joints"], 74);    // two across the width: not the neighbours' courses touching along an edge
  EXPECT_EQ(stands["most"], 0) << stands.dump();
  EXPECT_TRUE(stands["first_s"].is_null());

  const nlohmann::ordered_json collapses = arch_hinges(0.10).summary(0.0);
  std::printf("t/R = 0.10: %s\n", collapses.dump().c_str());
  ASSERT_EQ(collapses["most"], 5) << collapses.dump();
  const std::vector<double> angles = collapses["angles_deg"].get<std::vector<double>>();
  EXPECT_NEAR(angles[0], -90, 1e-6);
  EXPECT_GT(angles[1], -59.5);
  EXPECT_LT(angles[1], -52);
  EXPECT_NEAR(angles[2], 0, 1e-6);
  EXPECT_GT(angles[3], 52);
  EXPECT_LT(angles[3], 59.5);
  EXPECT_NEAR(angles[4], 90, 1e-6);
  EXPECT_LE(collapses["first_s"].get<double>(), collapses["most_at_s"].get<double>());
}

// A bridge's ring of two spans, two stones across its width: each span's radial joints make
// its own sections, at the ring's joint angles (geometry/arch_ring.h), and of two neighbouring
// sections opened by hand the one open more is the hinge.
TEST(HowItFails, RingSectionsArePerSpanAtTheJointsAnglesAndAHingeIsTheWiderOfNeighbours) {
  BridgeSpec spec;
  spec.ring.width_m = 1.28;  // two stones of 0.64 m across
  spec.ring.voussoirs = 33;
  spec.spans = 2;
  const Model m = compile_bridge(spec, generate_bridge(spec));
  World w(m, 1e-5);
  Joints joints = find_original_joints(w.state());
  RingHinges hinges(m, joints);
  EXPECT_EQ(hinges.note(joints, 0.0, false), 0);
  nlohmann::ordered_json h = hinges.summary(0.0);
  EXPECT_EQ(h["sections"], 2 * 32);
  EXPECT_EQ(h["joints"], 2 * 32 * 2);
  EXPECT_EQ(hinges.most(), 0);
  // Opens the joints of the section at `position` in the span at x > 0 (or x < 0) by `opening`.
  auto open = [&](int position, bool plus_x, double opening) {
    for (int j = 0; j < joints.size(); ++j) {
      const int a = joints.block_a[j], b = joints.block_b[j];
      if (m.block_tag[a].part != static_cast<int>(Part::ring) || m.block_tag[b].part != static_cast<int>(Part::ring)) continue;
      if (std::max(m.block_tag[a].course, m.block_tag[b].course) != position || m.block_tag[a].course == m.block_tag[b].course) continue;
      if ((m.initial_position[a].x() > 0) == plus_x) joints.opening_m[j] = opening;
    }
  };
  const RingGeometry g = ring_geometry(spec.ring);
  const double depth = spec.ring.thickness_m;
  open(5, true, 1.5 * kHingeRotationRad * depth);   // the +x span: one hinge at joint 5
  open(20, false, 1.5 * kHingeRotationRad * depth);  // the -x span: joints 20 and 21 open, 21 more
  open(21, false, 2.0 * kHingeRotationRad * depth);
  open(9, false, 0.9 * kHingeRotationRad * depth);   // below the rotation: no hinge
  EXPECT_EQ(hinges.note(joints, 1.0, false), 2);
  h = hinges.summary(0.5);
  ASSERT_EQ(h["most"], 2) << h.dump();
  EXPECT_NEAR(h["most_at_s"].get<double>(), 0.5, 1e-12);
  const auto angles = h["angles_deg"].get<std::vector<double>>();  // the -x span's first
  EXPECT_NEAR(angles[0], g.joint(21) * 180 / std::numbers::pi, 1e-6);
  EXPECT_NEAR(angles[1], g.joint(5) * 180 / std::numbers::pi, 1e-6);
  open(12, true, 2.0 * kHingeRotationRad * depth);
  EXPECT_EQ(hinges.note(joints, 1.1, true), 3);  // a ring stone fell: counted, no longer recorded
  EXPECT_EQ(hinges.most(), 2);
}

nlohmann::ordered_json part(const char* name, int fallen, double first_s, int minus_y, int middle, int plus_y) {
  return {{"part", name}, {"fallen", fallen}, {"first_fall_s", first_s}, {"sides", {{"-y", minus_y}, {"middle", middle}, {"+y", plus_y}}}};
}

TEST(HowItFails, TheSentenceNamesThePartsInTheOrderTheyFellAndAOneSidedWallsSide) {
  nlohmann::ordered_json how;
  // The wall lost 150 of its 180 on the -y side (over four in five: its side is said), the ring
  // 60 of 83 on the +y side (under four in five: not).
  how["parts"] = {part("wall", 180, 5.2, 150, 0, 30), part("ring", 83, 5.4, 20, 3, 60), part("fill", 57, 5.45, 0, 57, 0)};
  how["toward"] = {{"+x", 20}, {"-x", 28}, {"+y", 22}, {"-y", 250}};
  EXPECT_EQ(how_it_fails_text(how),
            "wall stones from 5.20 s of shaking (180, 150 of them on the -y side), ring stones from 5.40 s of shaking "
            "(83), then fill stones from 5.45 s of shaking (57); of the 320, 272 fell across the bridge (out of plane, "
            "250 toward -y) and 48 fell along the span (in plane, 28 toward -x)");
  EXPECT_EQ(failure_mode_of(how), "wall first (across)");  // 272 of 320: over two thirds
  how["toward"] = {{"+x", 20}, {"-x", 200}, {"+y", 22}, {"-y", 78}};
  EXPECT_EQ(failure_mode_of(how), "wall first (along)");  // 220 of 320
  how["parts"] = nlohmann::ordered_json::array();
  EXPECT_EQ(how_it_fails_text(how), "no stone fell");
  EXPECT_EQ(failure_mode_of(how), "no stone fell");
}

TEST(HowItFails, TheSentenceSaysWhereTheRingHingedAndWhetherBeforeItsStonesFell) {
  nlohmann::ordered_json how;
  how["parts"] = nlohmann::ordered_json::array({part("ring", 32, 5.6, 0, 32, 0)});
  how["toward"] = {{"+x", 0}, {"-x", 32}, {"+y", 0}, {"-y", 0}};
  how["ring_hinges"] = {{"sections", 32}, {"first_s", 4.2}, {"most", 5}, {"most_at_s", 4.4}, {"angles_deg", {-85.2, -55, 0, 55, 85.2}}};
  EXPECT_EQ(how_it_fails_text(how),
            "ring stones from 5.60 s of shaking (32); all 32 fell along the span (in plane, 32 toward -x); ring hinges "
            "from 4.20 s of shaking, at most 5 at once (at -85, -55, 0, 55 and 85 degrees from the crown, 4.40 s of "
            "shaking) before its first stone fell");
  EXPECT_EQ(failure_mode_of(how), "ring first (along)");  // the hinges do not change the mode
  how["parts"] = nlohmann::ordered_json::array();
  how["ring_hinges"] = {{"sections", 32}, {"first_s", 2.1}, {"most", 1}, {"most_at_s", 2.1}, {"angles_deg", {3}}};
  EXPECT_EQ(how_it_fails_text(how), "no stone fell; ring hinges from 2.10 s of shaking, at most 1 at once (at 3 degrees "
                                    "from the crown, 2.10 s of shaking)");
  how["ring_hinges"] = {{"sections", 32}, {"first_s", nullptr}, {"most", 0}, {"most_at_s", nullptr}, {"angles_deg", nlohmann::ordered_json::array()}};
  EXPECT_EQ(how_it_fails_text(how), "no stone fell; no ring joint hinged");
  how["ring_hinges"] = nullptr;  // a model without a ring
  EXPECT_EQ(how_it_fails_text(how), "no stone fell");
}

}  // namespace
}  // namespace ishibashi
