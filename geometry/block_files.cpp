#include "geometry/block_files.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <map>
#include <numeric>

#include "geometry/convex_hull.h"
#include "geometry/input_error.h"

namespace ishibashi {
namespace {

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Plain OFF, read here: CGAL 5.5's reader overruns a buffer on malformed colour entries
// (found by fuzzing). "OFF", the counts (vertices, faces, edges), x y z per vertex, then
// n i1 ... in per face; '#' starts a comment; anything after a vertex's z or a face's
// last index (a colour) is ignored.
void read_off(const std::filesystem::path& file, std::vector<Point>& points, std::vector<std::vector<std::size_t>>& polygons) {
  std::ifstream in(file);
  std::string line, header;
  int line_number = 0;
  auto next = [&](std::istringstream& fields) {  // the next line with content
    while (std::getline(in, line)) {
      ++line_number;
      line = line.substr(0, line.find('#'));
      if (line.find_first_not_of(" \t\r") != std::string::npos) {
        fields = std::istringstream(line);
        return true;
      }
    }
    throw InputError(file.string() + ": the file ends at line " + std::to_string(line_number) + " before the OFF data does");
  };
  auto fail = [&](const std::string& what) {
    throw InputError(file.string() + ":" + std::to_string(line_number) + ": " + what);
  };
  std::istringstream fields;
  next(fields);
  fields >> header;
  if (header != "OFF") fail("an OFF file starts with \"OFF\" (not " + header + "; coloured or other OFF variants are not read)");
  long nv = -1, nf = -1;
  if (!(fields >> nv)) next(fields), fields >> nv;
  if (!(fields >> nf) || nv < 0 || nf < 0 || nv > 10000000 || nf > 10000000)
    fail("expected the counts of vertices and faces (0 to 10,000,000 each)");
  for (long v = 0; v < nv; ++v) {
    next(fields);
    double x, y, z;
    if (!(fields >> x >> y >> z)) fail("expected the x y z of vertex " + std::to_string(v + 1));
    points.emplace_back(x, y, z);
  }
  for (long f = 0; f < nf; ++f) {
    next(fields);
    long n = 0;
    if (!(fields >> n) || n < 3 || n > 1000) fail("expected the corner count of face " + std::to_string(f + 1) + " (3 to 1,000)");
    std::vector<std::size_t> face;
    for (long k = 0; k < n; ++k) {
      long index = -1;
      if (!(fields >> index) || index < 0 || index >= nv)
        fail("face " + std::to_string(f + 1) + ": expected " + std::to_string(n) + " vertex indices from 0 to " + std::to_string(nv - 1));
      face.push_back(static_cast<std::size_t>(index));
    }
    polygons.push_back(face);
  }
}

}  // namespace

std::vector<Polyhedron> read_block_file(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": no such file");
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".off") read_off(file, points, polygons);  // throws with the line on bad input
  else if (!CGAL::IO::read_polygon_soup(file.string(), points, polygons)) polygons.clear();
  if (polygons.empty())
    throw InputError(file.string() + ": not a readable OFF, OBJ or STL mesh (or it holds no faces)");
  // CGAL reads what the file says: a face may name a vertex the file does not have.
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    if (polygons[i].size() < 3)
      throw InputError(file.string() + ": face " + std::to_string(i + 1) + " has " +
                               std::to_string(polygons[i].size()) + " corners; a face needs at least 3");
    for (std::size_t v : polygons[i])
      if (v >= points.size())
        throw InputError(file.string() + ": face " + std::to_string(i + 1) + " names vertex " + std::to_string(v + 1) +
                                 " of " + std::to_string(points.size()));
  }
  for (std::size_t v = 0; v < points.size(); ++v)
    if (!std::isfinite(points[v].x()) || !std::isfinite(points[v].y()) || !std::isfinite(points[v].z()))
      throw InputError(file.string() + ": vertex " + std::to_string(v + 1) + " has a coordinate that is not a number");
  // STL repeats every corner: merge equal points so that faces share vertices. (OFF and
  // OBJ index their vertices; merging there would weld touching blocks together.)
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
    throw std::runtime_error(file.string() + ": cannot write (a full disk, no permission, or not .off, .obj or .stl)");
}

Polyhedron merged_faces(const Polyhedron& convex_block) { return convex_hull(convex_block.vertices); }

}  // namespace ishibashi
