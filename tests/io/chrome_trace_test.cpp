// run --trace's timeline (io/chrome_trace.h): a Chrome trace-event JSON file whose events
// have the format's fields, whose slices nest on every thread's track and never overlap,
// a step per traced step on the caller's track holding its stages, and workers' slices
// inside the caller's slice of the same stage. Timing the threads changes no result.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "io/chrome_trace.h"

namespace ishibashi {
namespace {

World shaken_wall(int threads, long steps, bool trace) {
  omp_set_num_threads(threads);
  WallSpec spec;
  spec.courses = 5;
  spec.stones_per_course = 14;  // 141 blocks: enough for the loops to run on threads
  spec.leaves = 2;
  World w(make_wall_model(spec), 1e-5);
  w.set_adaptive_threads(false);
  if (trace) w.trace_steps(10, 210);  // long enough for a worker held off its core to come back
  for (long i = 0; i < steps; ++i) {
    w.state().velocity[0].x() += 0.8 * 9.81 * std::sin(2 * M_PI * 5.0 * w.state().time_s) * w.dt_s();
    w.step();
  }
  return w;
}

struct Slice {
  std::string name;
  long step;
  double begin_us, end_us;
};

TEST(ChromeTrace, SlicesNestOnEveryThreadAndStagesLieInTheirSteps) {
  const int saved = omp_get_max_threads();
  const World traced = shaken_wall(3, 220, true);
  const World plain = shaken_wall(3, 220, false);
  omp_set_num_threads(saved);
  EXPECT_EQ(traced.state_hash(), plain.state_hash());

  const auto file = std::filesystem::temp_directory_path() / "ishibashi_trace_test.json";
  write_chrome_trace(traced.trace(), "wall \"test\"", file);
  nlohmann::json doc;
  ASSERT_NO_THROW(doc = nlohmann::json::parse(std::ifstream(file))) << "not JSON";
  std::filesystem::remove(file);
  ASSERT_TRUE(doc.is_object());
  ASSERT_TRUE(doc["traceEvents"].is_array());

  std::map<int, std::vector<Slice>> tracks;
  int named_threads = 0;
  for (const auto& e : doc["traceEvents"]) {
    ASSERT_TRUE(e["name"].is_string());
    ASSERT_TRUE(e["pid"].is_number_integer());
    ASSERT_TRUE(e["tid"].is_number_integer());
    const std::string ph = e["ph"];
    if (ph == "M") {
      named_threads += e["name"] == "thread_name";
      ASSERT_TRUE(e["args"]["name"].is_string());
      continue;
    }
    ASSERT_EQ(ph, "X") << "complete events only";
    ASSERT_TRUE(e["ts"].is_number());
    ASSERT_TRUE(e["dur"].is_number());
    ASSERT_GE(e["dur"].get<double>(), 0.0);
    const double ts = e["ts"];
    if (e["cat"] == "stage") {  // a thread's part of a stage: the chunks it ran, some taken from another's range
      ASSERT_TRUE(e["args"]["busy_us"].is_number());
      ASSERT_TRUE(e["args"]["chunks"].is_number_integer());
      ASSERT_TRUE(e["args"]["stolen_chunks"].is_number_integer());
      EXPECT_GE(e["args"]["stolen_chunks"].get<int>(), 0);
      EXPECT_LE(e["args"]["stolen_chunks"].get<int>(), e["args"]["chunks"].get<int>());
    }
    tracks[e["tid"]].push_back({e["name"], e["args"]["step"], ts, ts + e["dur"].get<double>()});
  }
  EXPECT_EQ(named_threads, static_cast<int>(tracks.size()));
  ASSERT_TRUE(tracks.count(0));
  EXPECT_GE(tracks.size(), 2u) << "no worker ran a chunk of 200 steps";

  // Each track: sorted by start (longer first), every slice either inside the one open
  // around it or after it.
  for (auto& [tid, slices] : tracks) {
    std::sort(slices.begin(), slices.end(),
              [](const Slice& a, const Slice& b) { return a.begin_us != b.begin_us ? a.begin_us < b.begin_us : a.end_us > b.end_us; });
    std::vector<const Slice*> open;
    for (const Slice& s : slices) {
      while (!open.empty() && open.back()->end_us <= s.begin_us) open.pop_back();
      if (!open.empty()) {
        EXPECT_LE(s.end_us, open.back()->end_us) << "thread " << tid << ": " << s.name << " of step " << s.step
                                                 << " overlaps " << open.back()->name << " of step " << open.back()->step;
        EXPECT_EQ(s.step, open.back()->step) << "thread " << tid;
      } else {
        EXPECT_TRUE(s.name.rfind("step ", 0) == 0 || tid != 0) << s.name << " outside a step on the caller's track";
      }
      open.push_back(&s);
    }
  }

  // The caller's track: steps 10..209, each with the two stages of an explicit step (and
  // the broadphase first where it rebuilt the pair list): the pose rides on the last
  // step's integrate pass, a stage of its own only on a run's first step.
  std::map<long, std::vector<std::string>> stages_of_step;
  std::map<std::pair<long, std::string>, const Slice*> caller_stage;
  for (const Slice& s : tracks[0]) {
    if (s.name.rfind("step ", 0) == 0) continue;
    stages_of_step[s.step].push_back(s.name);
    caller_stage[{s.step, s.name}] = &s;
  }
  ASSERT_EQ(stages_of_step.size(), 200u);
  EXPECT_EQ(stages_of_step.begin()->first, 10);
  const std::vector<std::string> stages = {"narrowphase+contact law", "gather+integrate+pose"};
  const std::vector<std::string> rebuilding = {"broadphase", "narrowphase+contact law", "gather+integrate+pose"};
  for (const auto& [step, names] : stages_of_step)
    EXPECT_TRUE(names == stages || names == rebuilding) << "step " << step;
  // A worker's part of a stage lies inside the caller's slice of that stage.
  for (const auto& [tid, slices] : tracks) {
    if (tid == 0) continue;
    for (const Slice& s : slices) {
      const Slice* c = caller_stage.at({s.step, s.name});
      EXPECT_GE(s.begin_us, c->begin_us);
      EXPECT_LE(s.end_us, c->end_us);
    }
  }
}

// The profile's shares add up: work and waiting fill the team's time, the serial part is
// the caller's alone, the busiest thread works at least the mean.
TEST(ChromeTrace, ProfileSplitsTheTeamsTimeIntoWorkAndWaiting) {
  const int saved = omp_get_max_threads();
  const World w = shaken_wall(2, 200, true);
  omp_set_num_threads(saved);
  const Profile& p = w.state().profile;
  for (Stage stage : {Stage::pose, Stage::narrowphase_law, Stage::gather_integrate}) {
    const StageTime& t = p[stage];
    EXPECT_NEAR(t.team_s, 2 * t.wall_s, 1e-9);
    EXPECT_GT(t.work_s, 0);
    EXPECT_LE(t.work_s, t.team_s * (1 + 1e-9));
    EXPECT_LE(t.serial_s, t.wall_s);
    EXPECT_GE(t.imbalance(), 1.0 - 1e-9) << kStageNames[static_cast<int>(stage)];
  }
  // The contact law's part of the pass it shares with the narrowphase, by its own clock: the
  // wall's law does most of a step's work, yet less than the whole pass.
  const StageTime& shared = p[Stage::narrowphase_law];
  EXPECT_GT(shared.law_work_s, 0.2 * shared.work_s);
  EXPECT_LT(shared.law_work_s, shared.work_s);
}

}  // namespace
}  // namespace ishibashi
