#include "engine/mass_properties.h"

namespace ishibashi {

MassProperties polyhedron_mass_properties(const std::vector<Vec3>& vertices,
                                          const std::vector<std::vector<int>>& faces) {
  // Work relative to the vertex mean to keep round-off small far from the origin.
  Vec3 origin = Vec3::Zero();
  for (const Vec3& v : vertices) origin += v;
  origin /= static_cast<double>(vertices.size());

  // Each face is fanned into triangles (a, b, c); with the origin they make tetrahedra
  // whose signed volumes and second moments add up to the polyhedron's. For a
  // tetrahedron with one corner at the origin, integral of x x^T dV =
  // V/20 (sum_k p_k p_k^T + s s^T), s = sum_k p_k (the origin contributes zero).
  double volume = 0.0;
  Vec3 first_moment = Vec3::Zero();
  Mat3 second_moment = Mat3::Zero();
  for (const auto& face : faces) {
    const Vec3 a = vertices[face[0]] - origin;
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const Vec3 b = vertices[face[k]] - origin;
      const Vec3 c = vertices[face[k + 1]] - origin;
      const double v = a.dot(b.cross(c)) / 6.0;
      const Vec3 s = a + b + c;
      volume += v;
      first_moment += v * s / 4.0;
      second_moment += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
  }
  MassProperties out;
  out.volume_m3 = volume;
  if (volume == 0.0) return out;
  const Vec3 centroid = first_moment / volume;
  const Mat3 central = second_moment - volume * centroid * centroid.transpose();
  out.centroid_m = centroid + origin;
  out.inertia_per_density = central.trace() * Mat3::Identity() - central;
  return out;
}

}  // namespace ishibashi
