// Geometric validation of a block assembly with CGAL, run after generating or importing:
// each block closed, outward, convex, positive volume, no degenerate faces; no two blocks
// overlapping beyond a tolerance; every block meeting a neighbour on a shared face.
#pragma once
#include <string>
#include <vector>

#include "geometry/shapes.h"

namespace ishibashi {

struct ValidationReport {
  int blocks = 0;
  double volume_m3 = 0.0;        // sum of the blocks' volumes
  int overlapping_pairs = 0;
  int shared_faces = 0;          // pairs of blocks that meet on a face
  std::vector<std::string> errors;  // each names the block(s), position and fault
  bool ok() const { return errors.empty(); }
};

// `names` label the blocks in messages (may be empty). Two blocks overlap when their
// common volume exceeds overlap_tolerance_m3.
ValidationReport validate_blocks(const std::vector<Polyhedron>& blocks, const std::vector<std::string>& names,
                                 double overlap_tolerance_m3 = 1e-9);

}  // namespace ishibashi
