// Exact mass properties of a closed polyhedron (divergence theorem over a tetrahedral fan).
#pragma once
#include <vector>

#include "engine/math.h"

namespace ishibashi {

struct MassProperties {
  double volume_m3 = 0.0;  // signed: negative when the faces are inside out
  Vec3 centroid_m = Vec3::Zero();
  Mat3 inertia_per_density = Mat3::Zero();  // about the centroid, m^5 (multiply by density)
};

// Faces list vertex indices counter-clockwise seen from outside; any planar polygon.
MassProperties polyhedron_mass_properties(const std::vector<Vec3>& vertices,
                                          const std::vector<std::vector<int>>& faces);

}  // namespace ishibashi
