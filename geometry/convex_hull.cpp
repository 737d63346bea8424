#include "geometry/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <map>
#include <stdexcept>

namespace ishibashi {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

Polyhedron convex_hull(const std::vector<Vec3>& points) {
  std::vector<Kernel::Point_3> pts;
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  Mesh mesh;
  CGAL::convex_hull_3(pts.begin(), pts.end(), mesh);
  if (mesh.number_of_faces() < 4) throw std::invalid_argument("convex_hull: the points span no volume");

  Polyhedron out;
  std::map<Mesh::Vertex_index, int> index;
  for (Mesh::Vertex_index v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    index[v] = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  double extent = 0.0;
  for (const Vec3& v : out.vertices) extent = std::max(extent, (v - out.vertices[0]).norm());

  // Group hull triangles by their plane (unit normal and offset within round-off).
  struct Plane {
    Vec3 n;
    double d;
    std::vector<std::array<int, 3>> triangles;
  };
  std::vector<Plane> planes;
  for (Mesh::Face_index f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t[k++] = index[v];
    const Vec3 n = (out.vertices[t[1]] - out.vertices[t[0]]).cross(out.vertices[t[2]] - out.vertices[t[0]]).normalized();
    const double d = n.dot(out.vertices[t[0]]);
    Plane* found = nullptr;
    for (Plane& p : planes)
      if ((p.n - n).norm() < 1e-9 && std::abs(p.d - d) < 1e-9 * extent) found = &p;
    if (!found) {
      planes.push_back(Plane{n, d, {}});
      found = &planes.back();
    }
    found->triangles.push_back(t);
  }
  // Each group's boundary (directed edges whose reverse is not in the group) is one loop.
  for (const Plane& p : planes) {
    std::map<int, int> next;
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : p.triangles)
      for (int k = 0; k < 3; ++k) edges[{t[k], t[(k + 1) % 3]}] = 1;
    for (const auto& [e, unused] : edges)
      if (!edges.count({e.second, e.first})) next[e.first] = e.second;
    std::vector<int> loop;
    int v = next.begin()->first;
    do {
      loop.push_back(v);
      v = next.at(v);
    } while (v != loop.front() && loop.size() <= next.size());
    out.faces.push_back(loop);
  }
  return out;
}

}  // namespace ishibashi
