// `ishibashi build` of imported meshes: the units they are drawn in.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "command_line.h"
#include "geometry/block_files.h"

namespace ishibashi {
namespace {

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;

// The imported example (three stones on a slab) drawn in millimetres, as CAD programs
// draw: read as metres it builds stones of 600 m that would stand and shake as plausibly as
// the real ones, so the build warns; with [import] scale = 0.001 it is the example again,
// its mass and extent those of the metre files.
TEST(Build, AMeshInMillimetresIsWarnedOfAndScaleReadsIt) {
  const auto dir = test::tmp_dir() / "ishibashi_millimetres";
  std::filesystem::create_directories(dir);
  for (const char* name : {"stack_of_three.off", "base.off"}) {
    std::vector<Polyhedron> blocks = read_block_file(kRoot / "models/examples" / name);
    for (Polyhedron& p : blocks)
      for (Vec3& v : p.vertices) v *= 1000;
    write_block_file(dir / name, blocks);
  }
  const std::string import = "[import]\nfiles = [\"stack_of_three.off\"]\nfixed_files = [\"base.off\"]\n";
  std::ofstream(dir / "mm.toml") << import;
  std::ofstream(dir / "scaled.toml") << import << "scale = 0.001\n";
  auto build = [&](const std::filesystem::path& model, int* status) {
    return test::run_command(test::program() + " build " + model.string() + " --out " + (dir / "build").string(), status);
  };
  auto line_of = [](const std::string& text, const std::string& start) {
    const std::size_t at = text.find(start);
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  };
  int status = 0;
  const std::string mm = build(dir / "mm.toml", &status);
  ASSERT_EQ(status, 0) << mm;
  EXPECT_NE(mm.find("mm.toml: its largest free block is 600 m across; mesh coordinates are read as metres times [import] "
                    "scale: a mesh drawn in millimetres needs scale = 0.001"),
            std::string::npos) << mm;
  const std::string scaled = build(dir / "scaled.toml", &status), metres = build(kRoot / "models/examples/stack_of_three.toml", &status);
  ASSERT_EQ(status, 0) << metres;
  EXPECT_EQ(scaled.find("warning"), std::string::npos) << scaled;
  EXPECT_EQ(metres.find("warning"), std::string::npos) << metres;
  EXPECT_NE(line_of(scaled, "bounding box: x -2.000 .. 2.000"), "") << scaled;
  EXPECT_EQ(line_of(scaled, "mass of the free blocks"), line_of(metres, "mass of the free blocks")) << scaled << metres;
  EXPECT_NE(line_of(metres, "mass of the free blocks"), "");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ishibashi
