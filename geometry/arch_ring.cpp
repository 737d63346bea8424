#include "geometry/arch_ring.h"

#include <cmath>
#include <sstream>

#include "geometry/demo_scenes.h"

namespace ishibashi {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw ModelError("arch ring: " + what);
}

// Block between two radial joint planes (angles a0 < a1 from the crown, measured about
// y, positive towards +x), radii r_in .. r_out about `centre`, from y0 to y1.
Polyhedron voussoir(const Vec3& centre, double r_in, double r_out, double a0, double a1, double y0, double y1) {
  auto at = [&](double r, double a, double y) { return Vec3(centre.x() + r * std::sin(a), y, centre.z() + r * std::cos(a)); };
  Polyhedron p;
  // 0-3 at y0: (in,a0) (in,a1) (out,a1) (out,a0); 4-7 the same at y1.
  for (double y : {y0, y1}) {
    p.vertices.push_back(at(r_in, a0, y));
    p.vertices.push_back(at(r_in, a1, y));
    p.vertices.push_back(at(r_out, a1, y));
    p.vertices.push_back(at(r_out, a0, y));
  }
  p.faces = {
      {0, 1, 2, 3},  // y = y0 side, seen from -y
      {4, 7, 6, 5},  // y = y1 side
      {0, 4, 5, 1},  // intrados (faces the centre)
      {3, 2, 6, 7},  // extrados
      {0, 3, 7, 4},  // joint at a0
      {1, 5, 6, 2},  // joint at a1
  };
  // Orientation depends on the handedness of (angle, radius, y): check with the volume.
  Vec3 c = Vec3::Zero();
  for (const Vec3& v : p.vertices) c += v / 8.0;
  const auto& f = p.faces[0];
  const Vec3 n = (p.vertices[f[1]] - p.vertices[f[0]]).cross(p.vertices[f[2]] - p.vertices[f[0]]);
  if (n.dot(p.vertices[f[0]] - c) < 0)
    for (auto& face : p.faces) std::reverse(face.begin(), face.end());
  return p;
}

}  // namespace

std::vector<Voussoir> make_arch_ring(const ArchRingSpec& s) {
  require(s.span_m > 0, "span_m must be positive");
  require(s.rise_m > 0, "rise_m must be positive");
  require(s.rise_m <= 0.5 * s.span_m + 1e-12,
          "rise_m (" + std::to_string(s.rise_m) + ") must not exceed half the span (" + std::to_string(0.5 * s.span_m) +
              ") for a segmental or semicircular arch");
  require(s.thickness_m > 0, "thickness_m must be positive");
  require(s.width_m > 0, "width_m must be positive");
  require(s.stone_m > 0, "stone_m must be positive");
  require(s.stone_m <= s.width_m, "stone_m must not exceed the ring width");

  // Intrados circle through both springings and the crown.
  const double half = 0.5 * s.span_m;
  const double radius = (half * half + s.rise_m * s.rise_m) / (2.0 * s.rise_m);
  const double half_angle = std::asin(std::min(1.0, half / radius));  // pi/2 for a semicircle
  const Vec3 centre(0, 0, s.rise_m - radius);
  require(2.0 * half_angle * (radius + s.thickness_m) >= 3 * s.stone_m, "stone_m is too large for the ring (fewer than 3 voussoirs)");

  const double mid = radius + 0.5 * s.thickness_m;
  const int along = std::max(3, static_cast<int>(std::lround(2.0 * half_angle * mid / s.stone_m)));
  const int across = std::max(1, static_cast<int>(std::lround(s.width_m / s.stone_m)));
  const double da = 2.0 * half_angle / along, dy = s.width_m / across;

  std::vector<Voussoir> out;
  for (int i = 0; i < along; ++i) {
    const double a0 = -half_angle + i * da, a1 = a0 + da;
    // Running bond: every other ring of voussoirs is shifted by half a stone across the
    // width, with half stones at both faces.
    std::vector<double> cuts;
    const bool shifted = s.bond == Bond::running && i % 2 == 1 && across > 1;
    cuts.push_back(0.0);
    for (int k = 1; k < across + (shifted ? 1 : 0); ++k) cuts.push_back((k - (shifted ? 0.5 : 0.0)) * dy);
    cuts.push_back(s.width_m);
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double y0 = cuts[k] - 0.5 * s.width_m, y1 = cuts[k + 1] - 0.5 * s.width_m;
      out.push_back(Voussoir{voussoir(centre, radius, radius + s.thickness_m, a0, a1, y0, y1), i, static_cast<int>(k),
                             i == 0 || i == along - 1});
    }
  }
  return out;
}

Model make_arch_ring_model(const ArchRingSpec& s) {
  ModelBuilder builder;
  const int stone = builder.add_material(s.stone.name.empty() ? nishida_stone() : s.stone);
  for (const Voussoir& v : make_arch_ring(s))
    builder.add_block(v.shape.vertices, v.shape.faces, stone, v.fixed ? Motion::fixed : Motion::free,
                      "ring-" + std::to_string(v.ring_index) + "-" + std::to_string(v.course));
  return builder.build();
}

}  // namespace ishibashi
