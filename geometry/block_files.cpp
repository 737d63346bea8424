#include "geometry/block_files.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>

#include <algorithm>
#include <map>
#include <numeric>

#include "geometry/convex_hull.h"

namespace ishibashi {
namespace {

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<Polyhedron> read_block_file(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw std::runtime_error(file.string() + ": no such file");
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_polygon_soup(file.string(), points, polygons) || polygons.empty())
    throw std::runtime_error(file.string() + ": not a readable OFF, OBJ or STL mesh (or it holds no faces)");
  // STL repeats every corner: merge equal points so that faces share vertices. (OFF and
  // OBJ index their vertices; merging there would weld touching blocks together.)
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".stl") CGAL::Polygon_mesh_processing::merge_duplicate_points_in_polygon_soup(points, polygons);

  // Components: faces joined through shared vertices (union-find over the vertices).
  std::vector<int> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& f : polygons)
    for (std::size_t k = 1; k < f.size(); ++k) parent[find(parent, static_cast<int>(f[k]))] = find(parent, static_cast<int>(f[0]));
  std::map<int, std::size_t> component_of_root;
  std::vector<Polyhedron> blocks;
  std::vector<std::map<std::size_t, int>> local;  // file vertex -> block vertex
  for (const auto& f : polygons) {
    const int root = find(parent, static_cast<int>(f[0]));
    auto [it, added] = component_of_root.emplace(root, blocks.size());
    if (added) {
      blocks.emplace_back();
      local.emplace_back();
    }
    Polyhedron& b = blocks[it->second];
    std::vector<int> face;
    for (std::size_t v : f) {
      auto [slot, fresh] = local[it->second].emplace(v, static_cast<int>(b.vertices.size()));
      if (fresh) b.vertices.emplace_back(points[v].x(), points[v].y(), points[v].z());
      face.push_back(slot->second);
    }
    b.faces.push_back(face);
  }
  return blocks;
}

void write_block_file(const std::filesystem::path& file, const std::vector<Polyhedron>& blocks) {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  for (const Polyhedron& b : blocks) {
    const std::size_t base = points.size();
    for (const Vec3& v : b.vertices) points.emplace_back(v.x(), v.y(), v.z());
    for (const auto& f : b.faces) {
      std::vector<std::size_t> face;
      for (int v : f) face.push_back(base + v);
      polygons.push_back(face);
    }
  }
  if (!CGAL::IO::write_polygon_soup(file.string(), points, polygons, CGAL::parameters::stream_precision(17)))
    throw std::runtime_error(file.string() + ": cannot write (unknown extension, or no permission)");
}

Polyhedron merged_faces(const Polyhedron& convex_block) { return convex_hull(convex_block.vertices); }

}  // namespace ishibashi
