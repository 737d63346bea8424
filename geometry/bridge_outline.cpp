#include "geometry/bridge_outline.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <cmath>
#include <list>

namespace ishibashi {
namespace {
using Point2 = OutlineKernel::Point_2;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<OutlineKernel>;
}  // namespace

void require_spec(bool ok, const std::string& what) {
  if (!ok) throw ModelError("bridge: " + what);
}

Polygon2 rectangle(double x0, double x1, double z0, double z1) {
  Polygon2 p;
  p.push_back(Point2(x0, z0));
  p.push_back(Point2(x1, z0));
  p.push_back(Point2(x1, z1));
  p.push_back(Point2(x0, z1));
  return p;
}

std::vector<Vec3> to_xz(const Polygon2& p) {
  std::vector<Vec3> out;
  Polygon2 q = p;
  if (q.orientation() == CGAL::CLOCKWISE) q.reverse_orientation();
  for (auto v = q.vertices_begin(); v != q.vertices_end(); ++v)
    out.emplace_back(CGAL::to_double(v->x()), 0.0, CGAL::to_double(v->y()));
  return out;
}

double area_xz(const std::vector<Vec3>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& u = p[i];
    const Vec3& w = p[(i + 1) % p.size()];
    a += u.x() * w.z() - w.x() * u.z();
  }
  return 0.5 * std::abs(a);
}

Ring2 ring_outline(const RingGeometry& g, double centre_x) {
  Ring2 r;
  r.centre_x = centre_x;
  for (int i = 0; i <= g.along; ++i) {
    const double a = g.joint(i);
    r.intrados.emplace_back(centre_x + g.radius * std::sin(a), 0.0, g.centre_z + g.radius * std::cos(a));
    r.extrados.emplace_back(centre_x + g.outer_radius * std::sin(a), 0.0, g.centre_z + g.outer_radius * std::cos(a));
  }
  // Springers are squared off: vertical outer face, flat top at the next joint's height.
  const int n = g.along;
  const Vec3& e0 = r.extrados[0];
  const Vec3& en = r.extrados[n];
  r.outline.push_back(Point2(e0.x(), 0.0));
  r.outline.push_back(Point2(en.x(), 0.0));
  r.outline.push_back(Point2(en.x(), r.extrados[n - 1].z()));
  for (int i = n - 1; i >= 1; --i) r.outline.push_back(Point2(r.extrados[i].x(), r.extrados[i].z()));
  r.outline.push_back(Point2(e0.x(), r.extrados[1].z()));
  return r;
}

bool cut_cell(const Polygon2& cell, const std::vector<Ring2>& rings, std::vector<Vec3>& out) {
  std::list<PolygonWithHoles2> pieces{PolygonWithHoles2(cell)};
  for (const Ring2& r : rings) {
    std::list<PolygonWithHoles2> next;
    for (const auto& p : pieces) CGAL::difference(p, r.outline, std::back_inserter(next));
    pieces.swap(next);
  }
  if (pieces.empty()) return false;
  // Drop vertices that lie on the line of their neighbours (exact predicate).
  Polygon2 boundary;
  if (pieces.size() == 1 && !pieces.front().has_holes()) {
    const Polygon2& raw = pieces.front().outer_boundary();
    const std::size_t m = raw.size();
    for (std::size_t i = 0; i < m; ++i)
      if (!CGAL::collinear(raw[(i + m - 1) % m], raw[i], raw[(i + 1) % m])) boundary.push_back(raw[i]);
  }
  if (boundary.size() < 3 || !boundary.is_convex()) {
    const auto box = cell.bbox();
    throw ModelError("bridge: internal error, the fill cell at x = " + std::to_string(box.xmin()) + " .. " +
                     std::to_string(box.xmax()) + ", z = " + std::to_string(box.ymin()) + " .. " +
                     std::to_string(box.ymax()) + " is not convex after cutting; please report the parameters");
  }
  out = to_xz(boundary);
  return area_xz(out) > 1e-12;
}

}  // namespace ishibashi
