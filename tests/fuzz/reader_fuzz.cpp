// Fuzz target of one input reader (ISHIBASHI_FUZZ_READER names it): every input must end
// in a valid result or a clear error (an exception with a message), never a crash, a hang
// or an unbounded allocation. A block file's blocks are validated too, as `build` does.
// Built with libFuzzer (clang, scripts/fuzz.sh), and as a replay program (any compiler;
// ISHIBASHI_FUZZ_REPLAY): `replay_corpus READER DIR...` runs a reader's committed corpus
// as a test.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <omp.h>

#include "analysis/run/checkpoint.h"
#include "engine/world.h"
#include "geometry/block_files.h"
#include "geometry/shapes.h"
#include "geometry/validate.h"
#include "io/ground_motion.h"
#include "io/model_file.h"
#include "io/scenario_file.h"
#include "io/study_file.h"
#include "io/sweep_file.h"

namespace {

using namespace ishibashi;

#ifdef ISHIBASHI_FUZZ_READER
const std::string reader_name = ISHIBASHI_FUZZ_READER;
#else
std::string reader_name;  // the replay's first argument
#endif

// The readers take paths: each input goes to a file named like the format wants.
std::filesystem::path input_file(const char* extension) {
  static const std::filesystem::path dir = [] {
    // In memory where there is a tmpfs: a million files written and read.
    const std::filesystem::path shm = "/dev/shm";
    auto d = (std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path()) /
             ("ishibashi_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / (std::string("input.") + extension);
}

// A stone on a prescribed one and a third apart (1 m cubes, one thread): what a checkpoint
// body is resumed into (`replay_corpus --checkpoint-seed FILE` writes a body of it, ten steps
// on, as the corpus's seed: the format's version changes it).
World checkpoint_world() {
  omp_set_num_threads(1);
  ModelBuilder b;
  const int mat = b.add_material(Material{});
  for (const Vec3& at : {Vec3(0, 0, 0.5), Vec3(0, 0, 1.5), Vec3(3, 0, 0.5)}) {
    const Polyhedron cube = make_box(at, Vec3(1, 1, 1));
    b.add_block(cube.vertices, cube.faces, mat, at.z() < 1 && at.x() == 0 ? Motion::prescribed : Motion::free);
  }
  return World(b.build(), 1e-5);
}

void read_input(const std::string& reader, const std::uint8_t* data, std::size_t size) {
  if (reader == "checkpoint") {  // the checkpoint's body (joints and State), resumed as a run does
    static const World fresh = checkpoint_world();
    static const Joints found = find_original_joints(fresh.state());
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    CheckpointReader r(in);
    Joints joints;
    visit_joints(r, joints);
    check_joints_fit(joints, found);
    World world = fresh;
    read_state(r, world.state());
    check_state_fits(world.state(), world.model());
    world.run(3);  // a body that fits must step: nothing it holds may index past an array
    return;
  }
  const char* extension = reader == "at2" ? "AT2" : reader == "knet" ? "EW" : reader == "columns" ? "csv"
                        : reader == "off" ? "off" : reader == "obj" ? "obj" : reader == "stl" ? "stl" : "toml";
  const std::filesystem::path file = input_file(extension);
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (reader == "at2") read_at2(file);
  else if (reader == "knet") read_knet(file);
  else if (reader == "columns") {
    // Each layout in turn: one column at dt, time and acceleration, a column of several
    // below a header, with and without a time column.
    for (const ColumnLayout& layout : {ColumnLayout{.dt_s = 0.01}, ColumnLayout{}, ColumnLayout{.column = 3, .header_lines = 1},
                                       ColumnLayout{.dt_s = 0.01, .column = 2}}) {
      try {
        read_columns(file, AccelerationUnit::g, layout);
      } catch (const InputError&) {
      }
    }
  }
  else if (reader == "model") read_model_file(file);
  else if (reader == "scenario") read_scenario(file);
  else if (reader == "study") read_study(file, false);
  else if (reader == "sweep") read_sweep(file);
  else if (reader == "off" || reader == "obj" || reader == "stl")
    validate_blocks(read_block_file(file), {});  // what `build` does with a user's blocks next
  else throw std::logic_error("unknown reader " + reader);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    read_input(reader_name, data, size);
  } catch (const std::logic_error& e) {
    if (std::strstr(e.what(), "unknown reader")) throw;
    // std::stod and friends (invalid_argument, out_of_range): their message is only the
    // function's name ("stod"), telling a user neither the file nor the line.
    if (dynamic_cast<const std::invalid_argument*>(&e) || dynamic_cast<const std::out_of_range*>(&e)) {
      std::fprintf(stderr, "bare conversion error: %s\n", e.what());
      __builtin_trap();
    }
  } catch (const std::exception& e) {
    if (std::strlen(e.what()) == 0) __builtin_trap();  // an error must say what is wrong
  }
  return 0;
}

#ifdef ISHIBASHI_FUZZ_REPLAY
// Replays files (the committed corpus) through the target: a test in every build.
int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--checkpoint-seed") == 0) {
    World world = checkpoint_world();
    world.run(10);
    std::ofstream file(argv[2], std::ios::binary);
    CheckpointWriter out(file);
    Joints joints = find_original_joints(world.state());
    visit_joints(out, joints);
    write_state(out, world.state());
    return 0;
  }
  if (argc < 3) {
    std::fprintf(stderr, "usage: replay_corpus READER DIR...\n");
    return 2;
  }
  reader_name = argv[1];
  int count = 0;
  for (int i = 2; i < argc; ++i)
    for (const auto& entry : std::filesystem::recursive_directory_iterator(argv[i])) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), {});
      LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      ++count;
    }
  std::printf("%s: %d inputs replayed\n", reader_name.c_str(), count);
  return count > 0 ? 0 : 1;
}
#endif
