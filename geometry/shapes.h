// Polyhedral block shapes as plain vertex and face lists (faces counter-clockwise seen
// from outside), ready for ModelBuilder::add_block. Units: m.
#pragma once
#include <vector>

#include "engine/math.h"

namespace ishibashi {

struct Polyhedron {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
};

// Axis-aligned box with the given centre and full edge lengths.
Polyhedron make_box(const Vec3& center, const Vec3& size);

// Right prism: a convex polygon (counter-clockwise seen from +z, any z ignored) swept
// from z = z_bottom to z = z_top.
Polyhedron make_prism(const std::vector<Vec3>& base, double z_bottom, double z_top);

// Right prism along y: a convex polygon given in the x-z plane (the y of its points is
// ignored, any orientation) swept from y = y0 to y = y1.
Polyhedron make_prism_xz(const std::vector<Vec3>& polygon_xz, double y0, double y1);

// Voussoir-like trapezoidal prism: bottom width `bottom_width` (along x) at z = 0, top
// width `top_width` at z = height, depth `depth` along y, symmetric about x = 0 and y = 0.
Polyhedron make_trapezoid_prism(double bottom_width, double top_width, double height, double depth);

// Rigid motion of a polyhedron: x -> rotation * x + translation.
Polyhedron transformed(const Polyhedron& p, const Mat3& rotation, const Vec3& translation);

}  // namespace ishibashi
