// Ensembles of runs (analysis/run/ensemble.h): the Wilson interval against hand arithmetic;
// a member's draws reproducible from its seed, different between members and seeds, within
// the tolerance; a member's run the same whatever the thread count; a perturbed bridge
// settles without overlaps, as the preset does; `run --members` runs, resumes and keeps
// finished members, runs a share (--member-range) whose folders merge with the others',
// counts in how many members each stone fell (ensemble.json, fallen_share.vtu),
// and under mpirun across ranks; and its row of the study's ensemble table is written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "analysis/model/compile_model.h"
#include "analysis/batch/ensemble.h"
#include "analysis/batch/member_runs.h"
#include "analysis/run/member_draw.h"
#include "command_line.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "geometry/validate.h"
#include "io/model_file.h"
#include "io/vtk_input.h"

namespace ishibashi {
namespace {

using namespace test;  // run_command, text_of, count_of, state_hash_of, kMpirunTwoRanks, kRoot, tmp_dir

TEST(Ensemble, WilsonIntervalAsByHand) {
  // 3 of 10, z = 1.96: centre (0.3 + 1.96^2 / 20) / (1 + 1.96^2 / 10) = 0.49208 / 1.38415 = 0.35551,
  // half-width 1.96 / 1.38415 * sqrt(0.3 * 0.7 / 10 + 1.96^2 / 400) = 1.41603 * 0.17494 = 0.24772.
  const std::array<double, 2> three = wilson_interval(3, 10);
  EXPECT_NEAR(three[0], 0.35551 - 0.24772, 2e-5);
  EXPECT_NEAR(three[1], 0.35551 + 0.24772, 2e-5);
  // None of 5: [0, z^2 / (n + z^2)] = [0, 3.8415 / 8.8415]; all of 10: [n / (n + z^2), 1].
  EXPECT_NEAR(wilson_interval(0, 5)[0], 0.0, 1e-12);
  EXPECT_NEAR(wilson_interval(0, 5)[1], 3.8415 / 8.8415, 1e-4);
  EXPECT_NEAR(wilson_interval(10, 10)[0], 10 / 13.8415, 1e-4);
  EXPECT_NEAR(wilson_interval(10, 10)[1], 1.0, 1e-12);
  EXPECT_EQ(wilson_interval(0, 0), (std::array<double, 2>{0.0, 1.0}));  // no members: nothing known
}

const LoadedModel& model_a() {
  static const LoadedModel a = load_model_or_scenario(kRoot / "models" / "nishida_a.toml");
  return a;
}

Model member_model(const EnsembleSpec& spec, int member) {
  Model m = model_a().model();
  perturb_model(m, spec, draw_member(spec, member));
  return m;
}

bool same_poses(const Model& a, const Model& b) {
  for (int i = 0; i < a.block_count; ++i)
    if (a.initial_position[i] != b.initial_position[i] || a.initial_orientation[i].coeffs() != b.initial_orientation[i].coeffs())
      return false;
  return true;
}

TEST(Ensemble, MembersDrawReproduciblyWithinTheTolerance) {
  EnsembleSpec spec;
  spec.seed = 7;
  spec.position_tolerance_m = 1e-4;
  const Model& nominal = model_a().model();
  const Model member = member_model(spec, 3);
  EXPECT_TRUE(same_poses(member, member_model(spec, 3)));  // the seed reproduces it, bit for bit
  EXPECT_FALSE(same_poses(member, member_model(spec, 4)));
  EnsembleSpec other = spec;
  other.seed = 8;
  EXPECT_FALSE(same_poses(member, member_model(other, 3)));
  EnsembleSpec none = spec;
  none.position_tolerance_m = 0;
  EXPECT_TRUE(same_poses(nominal, member_model(none, 3)));  // no tolerance: the preset's poses

  // Each free stone cut by at most t (its nearest face), placed within t / 2 along each axis
  // and turned by no more than t / 2 at its farthest corner. Fixed blocks stay.
  const double t = spec.position_tolerance_m;
  int free = 0, placed = 0;
  for (int b = 0; b < nominal.block_count; ++b) {
    const Vec3 shift = member.initial_position[b] - nominal.initial_position[b];
    if (nominal.motion[b] != Motion::free) {
      EXPECT_EQ(shift, Vec3::Zero()) << b;
      continue;
    }
    ++free;
    double nearest = INFINITY, nearest_cut = INFINITY;
    for (int f = nominal.face_begin[b]; f < nominal.face_begin[b + 1]; ++f) {
      nearest = std::min(nearest, nominal.face_offset_local[f]);
      nearest_cut = std::min(nearest_cut, member.face_offset_local[f]);
    }
    EXPECT_LE(nearest - nearest_cut, t * (1 + 1e-9)) << b;
    EXPECT_GE(nearest - nearest_cut, 0.0) << b;
    EXPECT_LE(shift.cwiseAbs().maxCoeff(), 0.5 * t) << b;
    const double turn = member.initial_orientation[b].angularDistance(nominal.initial_orientation[b]);
    EXPECT_LE(turn * member.radius_m[b], 0.5 * t * (1 + 1e-6)) << b;
    placed += shift.norm() > 0.1 * t;
  }
  EXPECT_GT(free, 100);
  EXPECT_GT(placed, free / 10) << "stones placed off their drawn position by more than t / 10";

  // Friction and amplitude, when they vary, are drawn in their ranges.
  spec.friction_angle_deg = {25, 35};
  spec.amplitude = {0.8, 1.2};
  const MemberDraw draw = draw_member(spec, 5);
  EXPECT_GE(draw.friction_angle_deg, 25);
  EXPECT_LT(draw.friction_angle_deg, 35);
  EXPECT_GE(draw.amplitude, 0.8);
  EXPECT_LT(draw.amplitude, 1.2);
  Model rough = model_a().model();
  perturb_model(rough, spec, draw);
  for (const PairLaw& law : rough.pair_law) EXPECT_DOUBLE_EQ(law.tan_friction, std::tan(draw.friction_angle_deg * M_PI / 180));
}

// A member's stones are moved after the model is built: a tie rod stays anchored where it was
// in its stones and is snug again in the member's pose (tightened on the bridge as built),
// not stretched or slack by the tolerance (a 30 mm rod over 3 m stretched by 0.1 mm: 4.6 kN).
TEST(Ensemble, TieRodsAreSnugInEachMembersPose) {
  ModelFile file = read_model_file(kRoot / "models" / "nishida_a.toml");
  file.ties.push_back(TieSpec{Vec3(0, -1.5, 5.08), Vec3(0, 1.5, 5.08), 0.03});
  const Model built = load_model(file, kRoot / "models" / "nishida_a.toml", ModelOptions{});
  EnsembleSpec spec;
  spec.seed = 7;
  spec.position_tolerance_m = 1e-4;
  Model m = built;
  perturb_model(m, spec, draw_member(spec, 2));
  const Tie& tie = m.ties.at(0);
  const Vec3 a = m.initial_position[tie.block_a] + m.initial_orientation[tie.block_a] * tie.anchor_a_local;
  const Vec3 b = m.initial_position[tie.block_b] + m.initial_orientation[tie.block_b] * tie.anchor_b_local;
  EXPECT_NE(tie.rest_length_m, built.ties[0].rest_length_m);  // the member's stones did move
  EXPECT_DOUBLE_EQ(tie.rest_length_m, (b - a).norm());
  EXPECT_EQ(tie.stiffness_n_m, built.ties[0].stiffness_n_m);
}

// summary.json's result columns of `r`, as a run writes them (RunRecorder::write_summary:
// a column without a value is null).
nlohmann::json result_summary(const SeismicRunResult& r) {
  nlohmann::json summary;
  for (const ResultColumn& c : result_columns())
    summary[c.name] = std::visit(
        [](const auto& v) -> nlohmann::json {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) return nullptr;
          else return v;
        },
        c.value(r));
  return summary;
}

// ensemble.csv's row of a member's summary: every column in order, and an empty field for a
// column an older program's summary lacks (the rods' columns before session 67) or gives as null.
TEST(Ensemble, AMembersRowLeavesColumnsItsSummaryLacksEmpty) {
  SeismicRunResult r;
  r.fallen_stones = 7;
  r.collapse = true;
  nlohmann::json summary = result_summary(r);
  const std::string whole = summary_csv_values(summary);
  EXPECT_EQ(std::count(whole.begin(), whole.end(), ','), static_cast<long>(result_columns().size()) - 1);
  summary.erase("peak_tie_tension_n");
  summary.erase("tie_rods");
  const std::string row = summary_csv_values(summary);
  std::vector<std::string> fields;
  std::stringstream split(row);
  for (std::string f; std::getline(split, f, ',');) fields.push_back(f);
  fields.resize(result_columns().size());  // a trailing empty field
  for (std::size_t k = 0; k < result_columns().size(); ++k) {
    const std::string name = result_columns()[k].name;
    if (name == "tie_rods" || name == "peak_tie_tension_n") EXPECT_EQ(fields[k], "") << name;
    if (name == "fallen_stones") EXPECT_EQ(fields[k], "7");
    if (name == "collapse") EXPECT_EQ(fields[k], "yes");
  }
}

// ensemble.json's spreads of two members made by hand: a member's first fall is the first
// row of its shaking with a fallen stone, in seconds of shaking (its time less the
// settling; a stone fallen while settling does not count), and a median of two is their mean.
TEST(Ensemble, FirstFallIsInSecondsOfShakingAndAMedianOfTwoIsTheirMean) {
  const auto out = tmp_dir() / "ensemble_by_hand";
  std::filesystem::remove_all(out);
  const double settle_s = 0.5, fall_s[2] = {1.25, 2.0};
  const int fallen[2] = {3, 8};
  OutcomeTable table;
  for (int k = 0; k < 2; ++k) {
    const auto folder = out / ("member_" + std::to_string(k));
    std::filesystem::create_directories(folder);
    SeismicRunResult r;
    r.fallen_stones = fallen[k];
    r.settle_time_s = settle_s;
    const nlohmann::json summary = result_summary(r);
    std::ofstream(folder / "summary.json") << summary.dump();
    std::ofstream(folder / "history.csv") << "time_s,phase,fallen_stones\n0.4,settle,1\n"
                                           << settle_s + fall_s[k] - 0.25 << ",shake,0\n"
                                           << settle_s + fall_s[k] << ",shake," << fallen[k] << "\n"
                                           << settle_s + fall_s[k] + 0.5 << ",shake," << fallen[k] << "\n";
    table.rows.push_back({k, folder, {}});
  }
  nlohmann::ordered_json j;
  write_outcomes(table, out / "ensemble.csv", j);
  EXPECT_NEAR(j["first_fall_s"]["min"].get<double>(), 1.25, 1e-12);
  EXPECT_NEAR(j["first_fall_s"]["max"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(j["first_fall_s"]["median"].get<double>(), 1.625, 1e-12);
  EXPECT_NEAR(j["fallen_stones"]["median"].get<double>(), 5.5, 1e-12);
}

// A stone's draws go with where it stands, not with its block number: model A numbered
// backwards draws the same cut, shift and turn for every stone of member 3.
TEST(Ensemble, MembersDrawTheSameStonesWhateverTheNumbering) {
  const ModelFile file = read_model_file(kRoot / "models" / "nishida_a.toml");
  std::vector<BridgeBlock> blocks = generate_bridge(file.bridge);
  EnsembleSpec spec;
  spec.seed = 7;
  spec.position_tolerance_m = 1e-4;
  auto member = [&] {
    Model m = compile_bridge(file.bridge, blocks);
    perturb_model(m, spec, draw_member(spec, 3));
    return m;
  };
  const Model forwards = member();
  std::reverse(blocks.begin(), blocks.end() - 1);  // the ground slab stays last
  const Model backwards = member();
  const int n = forwards.block_count;
  int moved = 0;
  for (int b = 0; b < n - 1; ++b) {
    const int r = n - 2 - b;  // the same stone, numbered backwards
    EXPECT_NEAR((forwards.initial_position[b] - backwards.initial_position[r]).norm(), 0.0, 1e-12) << "block " << b;
    EXPECT_NEAR(forwards.initial_orientation[b].angularDistance(backwards.initial_orientation[r]), 0.0, 1e-12) << "block " << b;
    EXPECT_NEAR(forwards.radius_m[b], backwards.radius_m[r], 1e-12) << "block " << b;
    moved += forwards.motion[b] == Motion::free;
  }
  EXPECT_GT(moved, 100);
}

std::uint64_t member_hash_after(int threads, int steps) {
  omp_set_num_threads(threads);
  EnsembleSpec spec;
  spec.seed = 11;
  World w(member_model(spec, 2), 8e-6);
  w.set_adaptive_threads(false);
  for (int i = 0; i < steps; ++i) w.step();
  return w.state_hash();
}

TEST(Ensemble, MemberRunsTheSameWhateverTheThreads) {
  const int saved = omp_get_max_threads();
  const std::uint64_t one = member_hash_after(1, 400);
  EXPECT_EQ(member_hash_after(2, 400), one);
  EXPECT_EQ(member_hash_after(3, 400), one);
  omp_set_num_threads(saved);
}

// The blocks of a World in their current poses, for the CGAL check.
std::vector<Polyhedron> posed_blocks(const World& w) {
  const Model& m = w.model();
  std::vector<Polyhedron> blocks(m.block_count);
  for (int b = 0; b < m.block_count; ++b) {
    Polyhedron& p = blocks[b];
    for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v)
      p.vertices.push_back(w.state().orientation[b] * m.vertex_local[v] + w.state().position[b]);
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) {
      std::vector<int>& face = p.faces.emplace_back();
      for (int k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) face.push_back(m.face_vertex[k] - m.vertex_begin[b]);
    }
  }
  return blocks;
}

// Overlapping pairs of model A (or its member) after 0.25 s of settling under gravity,
// beyond 1e-7 m^3: the springs' own penetration under the stones' weight is microns over
// joints of a tenth of a square metre, 1e-7 m^3 a micron over the largest.
int overlaps_after_settling(const Model& m) {
  World w(m, 8e-6);
  while (w.state().time_s < 0.25) w.step();
  return validate_blocks(posed_blocks(w), {}, 1e-7).overlapping_pairs;
}

TEST(Ensemble, PerturbedBridgeSettlesWithoutOverlapsAsThePresetDoes) {
  EnsembleSpec spec;
  spec.seed = 3;
  EXPECT_EQ(overlaps_after_settling(model_a().model()), 0);
  EXPECT_EQ(overlaps_after_settling(member_model(spec, 1)), 0);
}

// Model A, 0.05 s of settling and 0.05 s of the strongest Kobe pulses, a frame every 0.01 s.
std::filesystem::path short_scenario(const std::string& name, const std::string& ensemble_table) {
  const auto f = tmp_dir() / name;
  const auto kobe = kRoot / "data/ground_motions/kobe_1995_jma";
  std::ofstream(f) << "[model]\nfile = \"" << (kRoot / "models/nishida_a.toml").string() << "\"\n"
                   << "[run]\nsettle_max_s = 0.05\nduration_s = 0.05\noutput_interval_s = 0.01\n"
                   << "[ground_motion]\nstart_s = 7.5\n"
                   << "x = { file = \"" << (kobe / "RSN1106_KOBE_KJM090.AT2").string() << "\" }\n"
                   << "y = { file = \"" << (kobe / "RSN1106_KOBE_KJM000.AT2").string() << "\" }\n"
                   << "z = { file = \"" << (kobe / "RSN1106_KOBE_KJM-UP.AT2").string() << "\" }\n"
                   << ensemble_table;
  return f;
}

// A member's settling (minutes of a large bridge) comes into the ensemble's log as lines,
// every 0.25 s of it, where a member said nothing until its shaking's first tenth.
TEST(Ensemble, MembersSettlingComesAsLines) {
  const auto file = short_scenario("ensemble_settling.toml", "[ensemble]\nmembers = 1\n");
  const auto out = tmp_dir() / "ensemble_settling";
  std::filesystem::remove_all(out);
  int status = 0;
  const std::string log = run_command(test::program() + " run " + file.string() +
                                          " --settle-max 0.3 --settle-kinetic 1e-12 --duration 0.01 --no-report --out " + out.string(),
                                      &status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("member 0: settling, 0.2"), std::string::npos) << log;  // the first frame past 0.25 s
  EXPECT_NE(log.find(" s of at most 0.30 s, kinetic energy "), std::string::npos) << log;
  EXPECT_NE(log.find("(settled below 1e-12 J)"), std::string::npos) << log;
}

// [run] stop_at = "collapse" (--stop-at collapse): a member that collapses ends at its
// first frame that finds it collapsed, the same run as without the option up to there (its
// history a prefix of the whole run's, row for row), with the same verdict; a run that
// stands goes on to the record's end, its state the whole run's bit for bit.
TEST(Ensemble, StopAtCollapseEndsCollapsingMembersThere) {
  auto run = [](const std::string& scenario, const std::string& name, const std::string& options) {
    const auto out = tmp_dir() / name;
    std::filesystem::remove_all(out);
    int status = 0;
    const std::string log = run_command(test::program() + " run " + (kRoot / "scenarios/examples" / scenario).string() +
                                            " --threads 1 --no-report " + options + " --out " + out.string(),
                                        &status);
    EXPECT_EQ(status, 0) << log;
    return out;
  };
  // The tied stack topples whole within its 3 s (scenarios/results, tie rods).
  const auto whole = run("stack_of_three_tied_kobe.toml", "stop_at_whole", "--members 2 --jobs 2");
  const auto stop = run("stack_of_three_tied_kobe.toml", "stop_at_collapse", "--members 2 --jobs 2 --stop-at collapse");
  EXPECT_NE(text_of(stop / "ensemble.json").find("\"stop_at\": \"collapse\""), std::string::npos);
  // ensemble.csv, what scenarios/results keeps of an ensemble, says which members stopped.
  EXPECT_EQ(count_of(text_of(stop / "ensemble.csv"), ",yes\n"), 2) << text_of(stop / "ensemble.csv");
  EXPECT_EQ(count_of(text_of(whole / "ensemble.csv"), ",no\n"), 2) << text_of(whole / "ensemble.csv");
  // How each member fails, in ensemble.csv and counted in ensemble.json: the stones above
  // the rod's lower stone topple off the stack, the same way stopped at the collapse or not.
  const auto modes = nlohmann::json::parse(text_of(whole / "ensemble.json"))["failure_modes"];
  int counted = 0;
  for (const auto& [mode, members] : modes.items()) {
    EXPECT_EQ(mode.rfind("imported first (", 0), 0u) << mode;
    EXPECT_EQ(count_of(text_of(whole / "ensemble.csv"), "," + mode + ","), members.get<int>()) << mode;
    counted += members.get<int>();
  }
  EXPECT_EQ(counted, 2) << modes.dump();
  for (const char* member : {"member_000", "member_001"}) {
    const auto a = nlohmann::json::parse(text_of(whole / member / "summary.json"));
    const auto b = nlohmann::json::parse(text_of(stop / member / "summary.json"));
    ASSERT_TRUE(a["collapse"].get<bool>()) << member << ": no collapse, the test shows nothing";
    EXPECT_TRUE(b["collapse"].get<bool>()) << member;
    EXPECT_TRUE(b["stopped_early"].get<bool>()) << member;
    EXPECT_FALSE(a["stopped_early"].get<bool>()) << member;
    EXPECT_LT(b["shaking_time_s"].get<double>(), a["shaking_time_s"].get<double>() - 0.1) << member;
    const std::string history = text_of(stop / member / "history.csv");
    EXPECT_EQ(text_of(whole / member / "history.csv").substr(0, history.size()), history) << member;
  }
  // The loose stack's stones slide and rock apart, and all stay up: a plain run that stands.
  const auto stands = run("stack_of_three_kobe.toml", "stop_at_stands", "");
  const auto stands_too = run("stack_of_three_kobe.toml", "stop_at_stands_too", "--stop-at collapse");
  ASSERT_NE(text_of(stands / "summary.json").find("\"collapse\": false"), std::string::npos);
  EXPECT_NE(text_of(stands_too / "summary.json").find("\"stopped_early\": false"), std::string::npos);
  EXPECT_EQ(state_hash_of(stands_too), state_hash_of(stands));
  EXPECT_FALSE(state_hash_of(stands).empty());
}

TEST(Ensemble, RunMembersWritesProbabilitiesAndKeepsFinishedMembers) {
  const auto file = short_scenario("ensemble_a.toml", "[ensemble]\nmembers = 3\nseed = 5\namplitude = [0.9, 1.1]\n");
  const auto out = tmp_dir() / "ensemble_a";
  std::filesystem::remove_all(out);
  const std::string command = test::program() + " run " + file.string() + " --jobs 2 --out " + out.string();
  int status = 0;
  // Two machines' shares, members 0-1 here and 2 in another folder; merged by copying the
  // member's folder, then the whole ensemble keeps all three and writes the tables.
  const std::string first = run_command(command + " --member-range 0:2", &status);
  ASSERT_EQ(status, 0) << first;
  EXPECT_NE(first.find("members 0 to 1 here"), std::string::npos) << first;
  EXPECT_NE(first.find("2 ran"), std::string::npos) << first;
  // A line at every tenth of a member's shaking after its first frame (0.2 of it here).
  EXPECT_NE(first.find("member 1: 40 % of the shaking done, about "), std::string::npos) << first;
  EXPECT_NE(first.find("member 1: 80 % of the shaking done, about "), std::string::npos) << first;
  EXPECT_EQ(first.find("member 1: 100 %"), std::string::npos) << first;
  EXPECT_FALSE(std::filesystem::exists(out / "member_002"));
  // Each member that ran has its report, drawn where it ran, as a single run has.
  for (const char* member : {"member_000", "member_001"})
    EXPECT_EQ(text_of(out / member / "report.png").substr(0, 4), "\x89PNG") << member;
  EXPECT_NE(first.find("member_NNN/ (each member's run and its report.png)"), std::string::npos) << first;
  // The folder is the ensemble's, not a run's: --resume says how an ensemble goes on.
  const std::string resumed = run_command(test::program() + " run --resume " + out.string(), &status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << resumed;
  EXPECT_NE(resumed.find(": the folder of an ensemble or a chaos probe, whose members resume each from its own checkpoint"),
            std::string::npos) << resumed;
  const auto elsewhere = tmp_dir() / "ensemble_a_elsewhere";
  std::filesystem::remove_all(elsewhere);
  const std::string share = test::program() + " run " + file.string() + " --member-range 2:3 --out " +
                            elsewhere.string();
  ASSERT_EQ((run_command(share, &status), status), 0);
  std::filesystem::copy(elsewhere / "member_002", out / "member_002", std::filesystem::copy_options::recursive);
  const std::string merged = run_command(command, &status);
  ASSERT_EQ(status, 0) << merged;
  EXPECT_NE(merged.find("0 ran, 3 were current"), std::string::npos) << merged;
  EXPECT_NE(merged.find("ensemble.json, ensemble.png (every member through the shaking)"), std::string::npos) << merged;
  EXPECT_EQ(text_of(out / "ensemble.png").substr(0, 4), "\x89PNG");
  const std::string json = text_of(out / "ensemble.json");
  EXPECT_NE(json.find("\"finished\": 3"), std::string::npos) << json;
  EXPECT_NE(json.find("\"collapse\""), std::string::npos) << json;
  // Model A's ring: each member counted its hinges (none in these 0.05 s).
  EXPECT_EQ(nlohmann::json::parse(json)["most_ring_hinges"]["count"], 3) << json;
  const std::string csv = text_of(out / "ensemble.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;  // header and a row per member
  EXPECT_NE(text_of(out / "member_002" / "summary.json").find("\"index\": 2"), std::string::npos);

  // Again, with a fourth member: the three are kept, the fourth runs.
  const std::string second = run_command(command + " --members 4", &status);
  ASSERT_EQ(status, 0) << second;
  EXPECT_NE(second.find("1 ran, 3 were current"), std::string::npos) << second;

  // Each member lists its fallen stones (as many as it counts), and the ensemble counts in
  // how many members each fell. Given other lists (these short runs drop none), the tables
  // written again count them, and fallen_share.vtu colours each block by its share.
  const std::vector<std::vector<int>> fell = {{5, 7}, {7}, {}, {7, 9}};
  double peak_per_amplitude[4];  // each member's record is the scenario's times its amplitude draw
  for (int i = 0; i < 4; ++i) {
    const auto summary_file = out / ("member_00" + std::to_string(i)) / "summary.json";
    nlohmann::json summary = nlohmann::json::parse(text_of(summary_file));
    const double amplitude = summary["member"]["amplitude"].get<double>();
    EXPECT_GT(amplitude, 0.9);
    EXPECT_LT(amplitude, 1.1);
    peak_per_amplitude[i] = summary["ground_motion"]["peak_acceleration_m_s2"][1].get<double>() / amplitude;
    EXPECT_NEAR(peak_per_amplitude[i], peak_per_amplitude[0], 1e-12 * peak_per_amplitude[0]) << "member " << i;
    EXPECT_EQ(summary["fallen_blocks"].size(), summary["fallen_stones"].get<std::size_t>());
    summary["fallen_blocks"] = fell[i];
    std::ofstream(summary_file) << summary.dump(2);
  }
  ASSERT_EQ((run_command(command + " --members 4", &status), status), 0);
  const nlohmann::json falls = nlohmann::json::parse(text_of(out / "ensemble.json"))["fallen_blocks"];
  EXPECT_EQ(falls["members"], 4);
  EXPECT_EQ(falls["falls"], nlohmann::json::parse("[[5, 1], [7, 3], [9, 1]]")) << falls;
  vtkUnstructuredGrid* map = read_vtu(out / "fallen_share.vtu");
  vtkDataArray* block_id = map->GetCellData()->GetArray("block_id");
  vtkDataArray* fallen_share = map->GetCellData()->GetArray("fallen_share");
  ASSERT_NE(fallen_share, nullptr);
  ASSERT_EQ(map->GetNumberOfCells(), model_a().model().block_count);
  for (vtkIdType c = 0; c < map->GetNumberOfCells(); ++c) {
    const int b = static_cast<int>(block_id->GetTuple1(c));
    EXPECT_EQ(fallen_share->GetTuple1(c), b == 7 ? 0.75 : b == 5 || b == 9 ? 0.25 : 0.0) << "block " << b;
  }
  map->Delete();

  // Its row of the study's ensemble table (scripts/study_ensemble_row.py), written twice:
  // the second replaces the first.
  const auto table = tmp_dir() / "ensemble_a_rows.csv";
  std::filesystem::remove(table);
  const std::string row = "python3 " + (kRoot / "scripts/study_ensemble_row.py").string() + " " + out.string() +
                          " a dry study test " + table.string();
  for (int k = 0; k < 2; ++k) ASSERT_EQ((run_command(row, &status), status), 0);
  const std::string rows = text_of(table);
  EXPECT_EQ(rows.rfind("model,variant,members,p_collapse,", 0), 0u) << rows;
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 2) << rows;
  EXPECT_NE(rows.find("\na,dry,4,"), std::string::npos) << rows;
}

// Under `mpirun -np 2` rank 0 hands the members out to both ranks, and every member ends in
// the same state as on one machine (a member's run depends on its seed, not where it ran).
TEST(Ensemble, MpirunRanksRunTheSameMembersAsOneMachine) {
  const auto file = short_scenario("ensemble_mpi.toml", "[ensemble]\nmembers = 3\nseed = 7\n");
  const auto local = tmp_dir() / "ensemble_mpi_local", ranks = tmp_dir() / "ensemble_mpi_ranks";
  std::filesystem::remove_all(local);
  std::filesystem::remove_all(ranks);
  const std::string run = test::program() + " run " + file.string() + " --threads 1 --out ";
  int status = 0;
  const std::string one = run_command(run + local.string() + " --jobs 2", &status);
  ASSERT_EQ(status, 0) << one;
  const std::string two = run_command(kMpirunTwoRanks + run + ranks.string(), &status);
  ASSERT_EQ(status, 0) << two;
  EXPECT_NE(two.find("2 MPI ranks"), std::string::npos) << two;
  EXPECT_NE(two.find("3 ran, 0 were current"), std::string::npos) << two;
  EXPECT_GE(count_of(two, "(rank 1): done"), 1) << "rank 1 ran no member: " << two;
  EXPECT_EQ(count_of(two, "ensemble: 3 members"), 1) << "only rank 0 reports the ensemble: " << two;
  for (int i = 0; i < 3; ++i) {
    const std::string name = "member_00" + std::to_string(i);
    ASSERT_FALSE(state_hash_of(local / name).empty()) << name;
    EXPECT_EQ(state_hash_of(ranks / name), state_hash_of(local / name)) << name;
  }
  EXPECT_NE(text_of(ranks / "ensemble.json").find("\"finished\": 3"), std::string::npos);

  // A single run is not split across ranks: refused, rather than two ranks writing one folder.
  const auto single = short_scenario("ensemble_mpi_single.toml", "");
  const std::string refused =
      run_command(kMpirunTwoRanks + test::program() + " run " + single.string() + " --out " + (tmp_dir() / "single").string() + " 2>&1", &status);
  EXPECT_NE(status, 0) << refused;
  EXPECT_NE(refused.find("only an ensemble's or a chaos probe's members (--members N, --probe N) are handed out"), std::string::npos) << refused;
  EXPECT_FALSE(std::filesystem::exists(tmp_dir() / "single" / "summary.json"));
}

TEST(Ensemble, BadEnsembleTableNamesTheKeyAndWhatIsAllowed) {
  const auto file = short_scenario("ensemble_bad.toml", "[ensemble]\nmembers = 3\namplitude = [1.2, 0.8]\n");
  int status = 0;
  const std::string out = run_command(test::program() + " run " + file.string() + " 2>&1", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("'amplitude' must be [lo, hi]"), std::string::npos) << out;
  EXPECT_NE(out.find("ensemble_bad.toml"), std::string::npos) << out;
}

TEST(Ensemble, MemberRangeOutsideTheEnsembleSaysWhatFits) {
  const auto file = short_scenario("ensemble_range.toml", "[ensemble]\nmembers = 3\n");
  const std::string run = test::program() + " run " + file.string() + " --out " +
                          (tmp_dir() / "ensemble_range").string() + " --member-range ";
  int status = 0;
  const std::string beyond = run_command(run + "2:5 2>&1", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(beyond.find("member range 2:5"), std::string::npos) << beyond;
  EXPECT_NE(beyond.find("members 0 to 2"), std::string::npos) << beyond;
  EXPECT_NE(beyond.find("0 <= FROM < TO <= 3"), std::string::npos) << beyond;
  const std::string garbled = run_command(run + "two 2>&1", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(garbled.find("--member-range two: expected FROM:TO"), std::string::npos) << garbled;
  EXPECT_FALSE(std::filesystem::exists(tmp_dir() / "ensemble_range" / "member_000"));
}


}  // namespace
}  // namespace ishibashi
