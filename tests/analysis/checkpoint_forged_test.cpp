// A checkpoint body made by hand passes its checksum (which guards against damage only), yet
// the step indexes what it reads unchecked: a resume refuses a state, joints or fall record
// that do not fit the model with what is wrong, instead of stepping past an array's end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/run/checkpoint.h"
#include "analysis/run/how_it_fails.h"
#include "engine/world.h"
#include "geometry/shapes.h"

namespace ishibashi {
namespace {

// A stone on a prescribed one and a third stone apart, each a 1 m cube, after a few steps:
// a face pair with sub-contacts, and the ground's forces listed.
std::unique_ptr<World> two_stones_on_the_ground() {
  ModelBuilder b;
  const int mat = b.add_material(Material{});
  for (const Vec3& at : {Vec3(0, 0, 0.5), Vec3(0, 0, 1.5), Vec3(3, 0, 0.5)}) {
    const Polyhedron cube = make_box(at, Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat, at.z() < 1 && at.x() == 0 ? Motion::prescribed : Motion::free);
  }
  auto world = std::make_unique<World>(b.build(), 1e-5);
  world->run(10);
  return world;
}

// The state written and read back: the error's text, or "" when it was read and fits.
std::string refusal(const State& state, const Model& model) {
  std::stringstream bytes;
  CheckpointWriter out(bytes);
  write_state(out, state);
  CheckpointReader in(bytes);
  State read;
  try {
    read_state(in, read);
    check_state_fits(read, model);
  } catch (const CheckpointError& e) {
    return e.what();
  }
  return "";
}

TEST(CheckpointForged, PairRangeOutsideTheSubContactsIsRefused) {
  const auto world = two_stones_on_the_ground();
  ASSERT_FALSE(world->state().pairs.empty());
  for (const auto& [begin, count] : {std::pair{0, 2'000'000'000}, std::pair{-5, 1}, std::pair{0, -1}}) {
    State forged = world->state();
    forged.pairs[0].sub_begin = begin;
    forged.pairs[0].sub_count = count;
    EXPECT_NE(refusal(forged, world->model()).find("pair 0 names sub-contacts"), std::string::npos) << begin << " + " << count;
  }
}

// Each forgery is refused, and says what it found; the state as written is read back.
TEST(CheckpointForged, StateThatNamesWhatTheModelLacksIsRefused) {
  const auto world = two_stones_on_the_ground();
  const State& s = world->state();
  ASSERT_EQ(s.pairs.size(), 1u);
  const Pair& pair = s.pairs[0];
  ASSERT_TRUE(pair.axis_kind == 0 || pair.axis_kind == 1);
  ASSERT_GT(pair.sub_count, 0);
  ASSERT_FALSE(s.prescribed_entry.empty());
  EXPECT_EQ(refusal(s, world->model()), "");

  const std::vector<std::pair<std::string, std::function<void(State&)>>> forgeries = {
      {"a pair joins two blocks a < b of the model's 3", [](State& f) { f.pairs[0].b = 3; }},
      {"a pair joins two blocks a < b", [](State& f) { f.pairs[0].b = f.pairs[0].a; }},
      {"the pairs are listed once each, in order", [](State& f) {
         f.pairs.push_back(f.pairs[0]);
         f.pairs[1].sub_count = 0;
       }},
      {"axis kind 7", [](State& f) { f.pairs[0].axis_kind = 7; }},
      {"is no face of block", [](State& f) { f.pairs[0].axis_feature = 17; }},  // the third stone's
      {"beside its face", [](State& f) { f.pairs[0].beside_axis = 1000; }},
      {"joins blocks 0 and 2", [](State& f) { f.contacts.block_b[f.pairs[0].sub_begin] = 2; }},
      {"the sub-contacts' flags holds", [](State& f) { f.contacts.flags.pop_back(); }},
      {"orientations holds 2 entries where the model has 3", [](State& f) { f.orientation.pop_back(); }},
      {"tie tensions holds 1 entries where the model has 0", [](State& f) { f.tie_tension_n.push_back(1.0); }},
      {"the ground's moments before", [](State& f) { f.prescribed_entry_moment_before.clear(); }},
      {"no prescribed block", [](State& f) { f.prescribed_entry[0][1] = 1; }},
      {"block 1's position, orientation or velocity is not", [](State& f) { f.position[1].x() = std::nan(""); }},
      {"block 2's position, orientation or velocity is not", [](State& f) { f.angular_velocity[2].z() = INFINITY; }},
      {"block 1's orientation is no unit quaternion (norm 2", [](State& f) { f.orientation[1].coeffs() *= 2; }},
      {"its time is not a finite number", [](State& f) { f.time_s = std::nan(""); }},
  };
  for (const auto& [says, forge] : forgeries) {
    State forged = s;
    forge(forged);
    const std::string error = refusal(forged, world->model());
    EXPECT_NE(error.find(says), std::string::npos) << "wanted \"" << says << "\", got \"" << error << "\"";
  }
}

// The profile is read whole, as the last of the state: a bool byte other than 0 or 1 in it
// would be undefined to read (UBSan's bool check found it by fuzzing), so it is refused.
TEST(CheckpointForged, ProfileFlagOtherThanZeroOrOneIsRefused) {
  const auto world = two_stones_on_the_ground();
  std::stringstream written;
  CheckpointWriter out(written);
  write_state(out, world->state());
  std::string bytes = written.str();
  const std::size_t flag_at = bytes.size() - sizeof(Profile) + offsetof(Profile, threads_timed);
  for (const unsigned char byte : {0, 1, 2, 191}) {
    bytes[flag_at] = static_cast<char>(byte);
    std::stringstream forged(bytes);
    CheckpointReader in(forged);
    State read;
    if (byte <= 1) {
      EXPECT_NO_THROW(read_state(in, read));
    } else {
      try {
        read_state(in, read);
        ADD_FAILURE() << "the flag's byte " << int(byte) << " was read";
      } catch (const CheckpointError& e) {
        EXPECT_NE(std::string(e.what()).find("timed threads is the byte " + std::to_string(byte)), std::string::npos) << e.what();
      }
    }
  }
}

TEST(CheckpointForged, JointsOfAnotherModelAreRefused) {
  const auto world = two_stones_on_the_ground();
  const Joints found = find_original_joints(world->state());
  ASSERT_EQ(found.size(), 1);
  EXPECT_NO_THROW(check_joints_fit(found, found));
  Joints other = found;
  other.block_b[0] = 2;
  EXPECT_THROW(check_joints_fit(other, found), CheckpointError);
  Joints short_points = found;
  short_points.reference_on_a.pop_back();
  EXPECT_THROW(check_joints_fit(short_points, found), CheckpointError);
  Joints short_joints = found;
  short_joints.cracked.clear();
  EXPECT_THROW(check_joints_fit(short_joints, found), CheckpointError);
}

// A fall record read back must be for the model's blocks, its directions among those named.
TEST(CheckpointForged, FallRecordOfAnotherModelIsRefused) {
  auto read_into = [](FallRecord written, int blocks) {
    std::stringstream bytes;
    CheckpointWriter out(bytes);
    written.visit(out);
    CheckpointReader in(bytes);
    FallRecord read(blocks);
    read.visit(in);
  };
  EXPECT_NO_THROW(read_into(FallRecord(3), 3));
  EXPECT_THROW(read_into(FallRecord(3), 2), CheckpointError);
  std::stringstream bytes;  // one block, fallen toward a direction past the last
  CheckpointWriter out(bytes);
  out.field(std::vector<double>{1.0});
  out.field(std::vector<std::uint8_t>{9});
  CheckpointReader in(bytes);
  FallRecord read(1);
  EXPECT_THROW(read.visit(in), CheckpointError);
}

}  // namespace
}  // namespace ishibashi
