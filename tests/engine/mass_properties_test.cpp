// Mass properties against closed forms (cube, trapezoidal voussoir) and against an
// independent grid quadrature (random convex polyhedron).
#include <gtest/gtest.h>

#include <random>

#include "engine/mass_properties.h"
#include "engine/model.h"
#include "geometry/convex_hull.h"
#include "geometry/shapes.h"

namespace ishibashi {
namespace {

Material unit_density() {
  Material m;
  m.name = "unit";
  m.density_kg_m3 = 1.0;
  return m;
}

TEST(MassProperties, CubeMatchesClosedForm) {
  const double a = 0.64, rho = 1880.0;
  Material stone = unit_density();
  stone.density_kg_m3 = rho;
  ModelBuilder b;
  const int mat = b.add_material(stone);
  const Polyhedron cube = make_box(Vec3(1, 2, 3), Vec3(a, a, a));
  b.add_block(cube.vertices, cube.faces, mat);
  const Model m = b.build();
  const double mass = rho * a * a * a;
  EXPECT_NEAR(m.mass_kg[0], mass, 1e-12 * mass);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.inertia_kg_m2[0][k], mass * a * a / 6.0, 1e-10 * mass * a * a);
  EXPECT_NEAR((m.initial_position[0] - Vec3(1, 2, 3)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(m.radius_m[0], std::sqrt(3.0) * a / 2, 1e-12);
}

// Trapezoidal prism: half-width w(z) = p + q z for z in [0, h], depth L along y.
TEST(MassProperties, VoussoirWedgeMatchesClosedForm) {
  const double bottom = 0.5, top = 0.8, h = 0.64, depth = 1.2;
  const double p = bottom / 2, q = (top - bottom) / (2 * h);
  const double volume = depth * h * (bottom + top) / 2;
  const double z_c = h * (bottom + 2 * top) / (3 * (bottom + top));
  // Integrals over the solid (unit density), about the base plane's axis.
  const double int_x2 = depth * 2.0 / 3.0 * (std::pow(p + q * h, 4) - std::pow(p, 4)) / (4 * q);  // sum x^2 dV
  const double int_z2 = depth * 2.0 * (p * h * h * h / 3 + q * h * h * h * h / 4);               // sum z^2 dV
  const double int_y2 = volume * depth * depth / 12.0;
  const double int_zc2 = int_z2 - volume * z_c * z_c;  // about the centroid
  const double ixx = int_y2 + int_zc2, iyy = int_x2 + int_zc2, izz = int_x2 + int_y2;

  const Polyhedron wedge = make_trapezoid_prism(bottom, top, h, depth);
  const MassProperties mp = polyhedron_mass_properties(wedge.vertices, wedge.faces);
  EXPECT_NEAR(mp.volume_m3, volume, 1e-12);
  EXPECT_NEAR(mp.centroid_m.z(), z_c, 1e-12);
  EXPECT_NEAR(mp.centroid_m.x(), 0.0, 1e-12);
  EXPECT_NEAR(mp.inertia_per_density(0, 0), ixx, 1e-12);
  EXPECT_NEAR(mp.inertia_per_density(1, 1), iyy, 1e-12);
  EXPECT_NEAR(mp.inertia_per_density(2, 2), izz, 1e-12);
  EXPECT_NEAR(mp.inertia_per_density(0, 2), 0.0, 1e-12);

  // The same wedge turned and moved: the principal moments are the sorted closed forms.
  ModelBuilder b;
  const int mat = b.add_material(unit_density());
  const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Polyhedron moved = transformed(wedge, r, Vec3(5, -2, 7));
  b.add_block(moved.vertices, moved.faces, mat);
  const Model m = b.build();
  std::vector<double> expected{ixx, iyy, izz};
  std::sort(expected.begin(), expected.end());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.inertia_kg_m2[0][k], expected[k], 1e-10);
  EXPECT_NEAR((m.initial_position[0] - (r * Vec3(0, 0, z_c) + Vec3(5, -2, 7))).norm(), 0.0, 1e-12);
}

// A random convex polyhedron: the exact integrals against a midpoint-rule quadrature on
// a fine grid (an oracle independent of the divergence-theorem formulas).
TEST(MassProperties, RandomConvexPolyhedronMatchesGridQuadrature) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i) {
    Vec3 d(normal(rng), normal(rng), normal(rng));
    points.push_back(d.normalized().cwiseProduct(Vec3(0.8, 0.5, 0.3)));
  }
  const Polyhedron hull = convex_hull(points);
  const MassProperties mp = polyhedron_mass_properties(hull.vertices, hull.faces);

  std::vector<Vec3> n;
  std::vector<double> d;
  for (const auto& f : hull.faces) {
    const Vec3 nf = (hull.vertices[f[1]] - hull.vertices[f[0]]).cross(hull.vertices[f[2]] - hull.vertices[f[0]]).normalized();
    n.push_back(nf);
    d.push_back(nf.dot(hull.vertices[f[0]]));
  }
  const int cells = 160;
  const Vec3 lo(-0.8, -0.5, -0.3), hi(0.8, 0.5, 0.3);
  const Vec3 step = (hi - lo) / cells;
  const double dv = step.prod();
  double volume = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k) {
        const Vec3 x = lo + Vec3((i + 0.5) * step.x(), (j + 0.5) * step.y(), (k + 0.5) * step.z());
        bool inside = true;
        for (std::size_t f = 0; f < n.size() && inside; ++f) inside = n[f].dot(x) <= d[f];
        if (!inside) continue;
        volume += dv;
        first += dv * x;
        second += dv * x * x.transpose();
      }
  const Vec3 c = first / volume;
  const Mat3 central = second - volume * c * c.transpose();
  const Mat3 inertia = central.trace() * Mat3::Identity() - central;
  EXPECT_NEAR(mp.volume_m3, volume, 2e-3 * volume);
  EXPECT_NEAR((mp.centroid_m - c).norm(), 0.0, 2e-3);
  EXPECT_NEAR((mp.inertia_per_density - inertia).norm(), 0.0, 5e-3 * inertia.norm());
}

}  // namespace
}  // namespace ishibashi
