// Where a straight line runs inside blocks: for placing tie rods by rows ([[tie_row]]),
// whose anchors sit just inside the masonry's outer faces.
#pragma once
#include <optional>
#include <utility>
#include <vector>

#include "geometry/bridge.h"

namespace ishibashi {

// The smallest and largest t (m, with `direction` a unit vector) at which origin + t
// direction lies inside a free block, over every free block the line passes through (gaps
// between them included); nullopt when it passes through none. A line that touches a block
// at a point (a stretch under 1e-9 m) does not count; one along a face or an edge does (a
// rod placed on it then has its anchors on a joint, which ModelBuilder::add_tie refuses).
// Fixed blocks (the ground, abutments) are left out: a rod is anchored in stones that move.
std::optional<std::pair<double, double>> free_blocks_along_line(const std::vector<BridgeBlock>& blocks,
                                                                const Vec3& origin, const Vec3& direction);

}  // namespace ishibashi
