// Convex hull of a point set (CGAL), with coplanar hull triangles merged into one
// polygonal face each, so a box comes out with 6 faces, not 12 triangles.
#pragma once
#include <vector>

#include "geometry/shapes.h"

namespace ishibashi {

// Throws std::invalid_argument when the points span no volume.
Polyhedron convex_hull(const std::vector<Vec3>& points);

}  // namespace ishibashi
