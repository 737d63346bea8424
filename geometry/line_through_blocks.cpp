#include "geometry/line_through_blocks.h"

#include <algorithm>
#include <cmath>

namespace ishibashi {
namespace {

constexpr double kGrazing_m = 1e-9;

// The stretch [t0, t1] of the line inside one convex block, clipped by each face's plane
// (Newell's normal, outward for faces counter-clockwise seen from outside); empty when t0 >= t1.
std::pair<double, double> inside_block(const Polyhedron& p, const Vec3& origin, const Vec3& direction) {
  double t0 = -INFINITY, t1 = INFINITY;
  for (const std::vector<int>& face : p.faces) {
    Vec3 normal = Vec3::Zero(), centroid = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3& a = p.vertices[face[i]];
      const Vec3& b = p.vertices[face[(i + 1) % face.size()]];
      normal += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
      centroid += a;
    }
    if (normal.norm() == 0) continue;  // a degenerate face (validation reports it)
    normal.normalize();
    centroid /= static_cast<double>(face.size());
    const double along = normal.dot(direction), room = normal.dot(centroid - origin);  // inside: along t <= room
    if (std::abs(along) < 1e-12) {
      if (room < 0) return {0, 0};  // parallel to the face, outside it
    } else if (along > 0) {
      t1 = std::min(t1, room / along);
    } else {
      t0 = std::max(t0, room / along);
    }
  }
  return {t0, t1};
}

}  // namespace

std::optional<std::pair<double, double>> free_blocks_along_line(const std::vector<BridgeBlock>& blocks,
                                                                const Vec3& origin, const Vec3& direction) {
  std::optional<std::pair<double, double>> extent;
  for (const BridgeBlock& block : blocks) {
    if (block.fixed) continue;
    const auto [t0, t1] = inside_block(block.shape, origin, direction);
    if (!(t1 - t0 > kGrazing_m)) continue;
    if (!extent) extent = {t0, t1};
    extent->first = std::min(extent->first, t0);
    extent->second = std::max(extent->second, t1);
  }
  return extent;
}

}  // namespace ishibashi
