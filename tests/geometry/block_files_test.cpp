// Export and import of blocks through CGAL's OFF, OBJ and STL readers and writers.
#include <gtest/gtest.h>

#include <fstream>

#include "engine/mass_properties.h"
#include "geometry/arch_ring.h"
#include "geometry/block_files.h"
#include "geometry/input_error.h"

namespace ishibashi {
namespace {

TEST(BlockFiles, OffAndObjRoundTripGiveTheSameBlocks) {
  ArchRingSpec spec;
  std::vector<Polyhedron> blocks;
  for (const Voussoir& v : make_arch_ring(spec)) blocks.push_back(v.shape);
  for (const char* ext : {".off", ".obj"}) {
    const auto file = std::filesystem::temp_directory_path() / (std::string("ishibashi_ring") + ext);
    write_block_file(file, blocks);
    const std::vector<Polyhedron> back = read_block_file(file);
    ASSERT_EQ(back.size(), blocks.size()) << ext;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      const MassProperties a = polyhedron_mass_properties(blocks[i].vertices, blocks[i].faces);
      const MassProperties b = polyhedron_mass_properties(back[i].vertices, back[i].faces);
      EXPECT_NEAR(a.volume_m3, b.volume_m3, 1e-12) << ext << " block " << i;
      EXPECT_NEAR((a.centroid_m - b.centroid_m).norm(), 0.0, 1e-12) << ext << " block " << i;
      EXPECT_EQ(back[i].faces.size(), blocks[i].faces.size());
    }
  }
}

TEST(BlockFiles, StlTrianglesAreMergedIntoFaces) {
  // A unit cube as 12 STL triangles: read as one block, merged into 6 square faces.
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_cube.stl";
  {
    std::ofstream out(file);
    out << "solid cube\n";
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (const auto& q : quads)
      for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
        out << "facet normal 0 0 0\nouter loop\n";
        for (int v : t) out << "vertex " << c[v][0] << " " << c[v][1] << " " << c[v][2] << "\n";
        out << "endloop\nendfacet\n";
      }
    out << "endsolid cube\n";
  }
  const std::vector<Polyhedron> blocks = read_block_file(file);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].vertices.size(), 8u);
  EXPECT_EQ(blocks[0].faces.size(), 12u);
  const Polyhedron merged = merged_faces(blocks[0]);
  EXPECT_EQ(merged.faces.size(), 6u);
  EXPECT_NEAR(polyhedron_mass_properties(merged.vertices, merged.faces).volume_m3, 1.0, 1e-12);
}

TEST(BlockFiles, MissingOrMalformedFileIsAClearError) {
  // InputError: the command prints "input error" and exits with status 2, as for a bad scenario.
  EXPECT_THROW(read_block_file("/nonexistent/blocks.off"), InputError);
  const auto file = std::filesystem::temp_directory_path() / "ishibashi_bad.off";
  std::ofstream(file) << "OFF\n3 1 0\n0 0 0\n1 0\n";
  try {
    read_block_file(file);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ishibashi_bad.off:4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ishibashi
