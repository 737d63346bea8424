// `ishibashi build` of imported meshes: the units they are drawn in.
#include <gtest/gtest.h>

#include <algorithm>
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

// The tied B that ships: build names the stones each rod is anchored in, and every one of
// the 12 rods joins a stone of one spandrel wall to one of the other, 3.1 m apart (a tie
// anchored in fill or ring would not restrain the walls); an anchor that misses a stone is
// refused at its [[tie]]'s line.
TEST(Build, TheTiedBridgesRodsJoinItsTwoSpandrelWalls) {
  int status = 0;
  const std::string out = test::run_command(test::program() + " build " + (kRoot / "models/nishida_b_tied.toml").string() +
                                                " --out " + (test::tmp_dir() / "ishibashi_tied_build").string(), &status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("ties: 12 tie rods, d = 30 mm, f_y = 235 MPa, yield force 166 kN\n"), std::string::npos) << out;
  int rods = 0;
  for (std::size_t at = out.find("  tie "); at != std::string::npos; at = out.find("  tie ", at + 1), ++rods) {
    const std::string line = out.substr(at, out.find('\n', at) - at);
    const std::size_t to = line.find(" to ");
    ASSERT_NE(to, std::string::npos) << line;
    EXPECT_NE(line.substr(0, to).find("'wall-"), std::string::npos) << line;
    EXPECT_NE(line.substr(to).find("'wall-"), std::string::npos) << line;
    EXPECT_NE(line.find(", 3.10 m"), std::string::npos) << line;
  }
  EXPECT_EQ(rods, 12);
  // Model A's lines, a blank one, then the [[tie]], its anchor above the ring.
  const std::string model_a = test::text_of(kRoot / "models/nishida_a.toml");
  const auto model = test::tmp_dir() / "ishibashi_tie_in_the_air.toml";
  std::ofstream(model) << model_a << "\n[[tie]]\nfrom = [0, -1.5, 9]\nto = [0, 1.5, 5.08]\ndiameter_m = 0.03\n";
  const int tie_line = static_cast<int>(std::count(model_a.begin(), model_a.end(), '\n')) + 2;
  const std::string refused = test::run_command(test::program() + " build " + model.string() + " --out " +
                                                    (test::tmp_dir() / "ishibashi_tied_build").string(), &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(refused.find("ishibashi_tie_in_the_air.toml:" + std::to_string(tie_line) +
                         ": tie 0: its anchor at (0, -1.5, 9) m lies in no block; anchor a tie inside a stone"),
            std::string::npos) << refused;
}

// Model B with two [[tie_row]] tables instead of twelve [[tie]] tables: build places and
// describes the same rods, each named with its row's line.
TEST(Build, TieRowsPlaceRodsAcrossTheWidth) {
  const std::string model_b = test::text_of(kRoot / "models/nishida_b.toml");
  const auto model = test::tmp_dir() / "ishibashi_tie_rows.toml";
  std::ofstream(model) << model_b << "\n[[tie_row]]\nx_m = [-10.5, -7.5, -4.5, -1.5, 1.5, 4.5, 7.5, 10.5]\nz_m = 5.44\n"
                       << "diameter_m = 0.03\n\n[[tie_row]]\nx_m = [-10.5, -7.5, 7.5, 10.5]\nz_m = 3.52\ndiameter_m = 0.03\n";
  const int first_row = static_cast<int>(std::count(model_b.begin(), model_b.end(), '\n')) + 2, second_row = first_row + 5;
  int status = 0;
  const std::string out = test::run_command(test::program() + " build " + model.string() + " --out " +
                                                (test::tmp_dir() / "ishibashi_tie_rows_build").string(), &status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("ties: 12 tie rods, d = 30 mm, f_y = 235 MPa, yield force 166 kN\n"), std::string::npos) << out;
  EXPECT_NE(out.find("  tie 7 (line " + std::to_string(first_row) + "): "), std::string::npos) << out;
  EXPECT_NE(out.find("  tie 8 (line " + std::to_string(second_row) + "): "), std::string::npos) << out;
  EXPECT_NE(out.find("  tie 11 (line " + std::to_string(second_row) + "): "), std::string::npos) << out;
  EXPECT_NE(out.find(" at (10.500, -1.550, 3.520) to "), std::string::npos) << out;  // tie 11's anchors, 5 cm inside the walls
  EXPECT_NE(out.find(" at (10.500, 1.550, 3.520), 3.10 m\n"), std::string::npos) << out;
}

}  // namespace
}  // namespace ishibashi
