#include "geometry/shapes.h"

#include <algorithm>

namespace ishibashi {

Polyhedron make_prism(const std::vector<Vec3>& base, double z_bottom, double z_top) {
  Polyhedron p;
  const int n = static_cast<int>(base.size());
  for (const Vec3& v : base) p.vertices.emplace_back(v.x(), v.y(), z_bottom);
  for (const Vec3& v : base) p.vertices.emplace_back(v.x(), v.y(), z_top);
  std::vector<int> bottom, top;
  for (int k = 0; k < n; ++k) {
    bottom.push_back(n - 1 - k);  // seen from below: reversed
    top.push_back(n + k);
    const int k1 = (k + 1) % n;
    p.faces.push_back({k, k1, n + k1, n + k});
  }
  p.faces.push_back(bottom);
  p.faces.push_back(top);
  return p;
}

Polyhedron make_box(const Vec3& c, const Vec3& size) {
  const Vec3 h = 0.5 * size;
  return make_prism({Vec3(c.x() - h.x(), c.y() - h.y(), 0), Vec3(c.x() + h.x(), c.y() - h.y(), 0),
                     Vec3(c.x() + h.x(), c.y() + h.y(), 0), Vec3(c.x() - h.x(), c.y() + h.y(), 0)},
                    c.z() - h.z(), c.z() + h.z());
}

Polyhedron make_trapezoid_prism(double bottom_width, double top_width, double height, double depth) {
  // Trapezoid in the x-z plane, swept along y: build it as a prism along z, then turn.
  const double b = 0.5 * bottom_width, t = 0.5 * top_width;
  Polyhedron p = make_prism({Vec3(-b, 0, 0), Vec3(b, 0, 0), Vec3(t, height, 0), Vec3(-t, height, 0)},
                            -0.5 * depth, 0.5 * depth);
  // (x, y, z) -> (x, -z, y) maps the prism's height (y) to z, keeps it right-handed.
  Mat3 r;
  r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  return transformed(p, r, Vec3::Zero());
}

Polyhedron make_prism_xz(const std::vector<Vec3>& xz, double y0, double y1) {
  // Build the prism along z from (x, z) seen as (x, y), then map (x, y, z) -> (x, z, y).
  // Counter-clockwise order in (x, z) is needed; the axis swap mirrors, so faces flip.
  std::vector<Vec3> base;
  double twice_area = 0;
  for (std::size_t i = 0; i < xz.size(); ++i) {
    const Vec3& p = xz[i];
    const Vec3& q = xz[(i + 1) % xz.size()];
    twice_area += p.x() * q.z() - q.x() * p.z();
    base.emplace_back(p.x(), p.z(), 0.0);
  }
  if (twice_area < 0) std::reverse(base.begin(), base.end());
  Polyhedron p = make_prism(base, y0, y1);
  for (Vec3& v : p.vertices) v = Vec3(v.x(), v.z(), v.y());
  for (auto& f : p.faces) std::reverse(f.begin(), f.end());
  return p;
}

Polyhedron transformed(const Polyhedron& p, const Mat3& rotation, const Vec3& translation) {
  Polyhedron out = p;
  for (Vec3& v : out.vertices) v = rotation * v + translation;
  return out;
}

}  // namespace ishibashi
