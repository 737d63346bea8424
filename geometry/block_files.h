// Blocks from and to mesh files (OFF, OBJ, STL through CGAL's readers and writers).
// An OFF or OBJ file may hold one block or several components (faces joined by shared
// vertex indices), one block each. STL has no vertex indices: equal corners are merged,
// so an STL file holds one block, or several that do not touch.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "geometry/shapes.h"

namespace ishibashi {

// Reads every closed component of the file as one block, as the file gives it (faces
// may be triangles). Throws InputError naming the file (and the line) when it cannot be read.
std::vector<Polyhedron> read_block_file(const std::filesystem::path& file);

// Writes the blocks into one file (their components), format from the extension
// (.off, .obj, .stl). Throws std::runtime_error naming the file on failure.
void write_block_file(const std::filesystem::path& file, const std::vector<Polyhedron>& blocks);

// The same convex block with coplanar faces merged into polygons (as the engine wants a
// face to be one contact plane). Only for blocks already validated as convex.
Polyhedron merged_faces(const Polyhedron& convex_block);

}  // namespace ishibashi
