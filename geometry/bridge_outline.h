// The bridge generator's outlines in the x-z plane (CGAL, exact): each span's ring with its
// springers, and the cells of the fill cut around them. Internal to geometry/ (bridge.cpp,
// bridge_fill.cpp): no CGAL type leaves this library.
#pragma once
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <string>
#include <vector>

#include "geometry/arch_ring.h"

namespace ishibashi {

using OutlineKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Polygon2 = CGAL::Polygon_2<OutlineKernel>;  // points (x, z)

// Throws ModelError("bridge: " + what) unless ok: a BridgeSpec out of range.
void require_spec(bool ok, const std::string& what);

Polygon2 rectangle(double x0, double x1, double z0, double z1);
std::vector<Vec3> to_xz(const Polygon2& p);      // counter-clockwise, (x, 0, z)
double area_xz(const std::vector<Vec3>& p);      // of a polygon given as (x, 0, z), m^2

// One span's ring in the x-z plane: intrados and extrados points at the joint angles.
struct Ring2 {
  double centre_x;
  std::vector<Vec3> intrados, extrados;  // (x, 0, z), index 0 at the x < 0 springing
  Polygon2 outline;                      // ring + springers + opening: what fill avoids
};
Ring2 ring_outline(const RingGeometry& g, double centre_x);

// The part of rectangle `cell` outside every ring outline: one convex polygon by
// construction of the courses (each cell meets at most one chord of a ring). False when
// nothing (of area) is left.
bool cut_cell(const Polygon2& cell, const std::vector<Ring2>& rings, std::vector<Vec3>& out);

}  // namespace ishibashi
