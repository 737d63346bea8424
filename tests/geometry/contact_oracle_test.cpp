// The narrowphase against an independent exact computation (CGAL), for random convex
// blocks at random poses touching with small overlaps:
//  * face on face (random convex prisms, random in-plane turn and offset): the contact
//    area equals the area of the two faces' overlap polygon computed exactly with CGAL's
//    2-D Boolean operations, every sub-contact lies in that polygon, the normal is the
//    faces' normal and the gap is the overlap;
//  * corner, edge and face first (random convex hulls turned at random, lowered onto a
//    block's face): the overlap depth equals the extent along the contact normal of the
//    two blocks' intersection computed by CGAL (halfspace intersection), and the contact
//    points lie within it.
#include <gtest/gtest.h>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Convex_hull_3/dual/halfspace_intersection_3.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <random>

#include "engine/pipeline.h"
#include "geometry/convex_hull.h"
#include "geometry/shapes.h"
#include "scenes.h"

namespace ishibashi {
namespace {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;

struct PairContacts {
  std::vector<Vec3> point, normal;
  std::vector<double> gap, area;
  double nominal_area_m2 = 0;  // the model's area of a corner contact
  double slack_m = 0;          // corners this close outside a face's side still count (0.1 tolerance)
};

// The sub-contacts between a fixed block `a` and a free block `b`, as the engine finds them.
PairContacts contacts_between(const Polyhedron& a, const Polyhedron& b) {
  const Model m = test::stones_model({{&a, Motion::fixed}, {&b, Motion::free}});
  const State s = test::contacts_found(m);
  PairContacts c;
  c.nominal_area_m2 = m.point_contact_area_m2(0, 1);
  c.slack_m = 0.1 * m.contact_tolerance_m(0, 1);
  for (std::size_t i = 0; i < s.contacts.size(); ++i) {
    // The engine's normal points from its block_a to block_b: make it fixed -> free.
    const double sign = s.contacts.block_a[i] == 0 ? 1.0 : -1.0;
    c.point.push_back(s.contacts.point[i]);
    c.normal.push_back(sign * s.contacts.normal[i]);
    c.gap.push_back(s.contacts.gap_m[i]);
    c.area.push_back(s.contacts.area_m2[i]);
  }
  return c;
}

// A random convex polygon in the xy plane around the origin (angles sorted, radii 0.2-0.5 m).
std::vector<Vec3> random_polygon(std::mt19937& random) {
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), radius(0.2, 0.5);
  std::vector<double> angles(3 + random() % 6);
  for (double& a : angles) a = angle(random);
  std::sort(angles.begin(), angles.end());
  std::vector<Vec3> points;
  for (double a : angles) {
    const double r = radius(random);
    points.push_back(Vec3(r * std::cos(a), r * std::sin(a), 0));
  }
  // The hull of the points, counter-clockwise (exact predicates).
  std::vector<Inexact::Point_2> in, hull;
  for (const Vec3& p : points) in.emplace_back(p.x(), p.y());
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull));
  std::vector<Vec3> out;
  for (const auto& p : hull) out.push_back(Vec3(p.x(), p.y(), 0));
  return out;
}

CGAL::Polygon_2<Exact> exact_polygon(const std::vector<Vec3>& polygon) {
  CGAL::Polygon_2<Exact> p;
  for (const Vec3& v : polygon) p.push_back(Exact::Point_2(v.x(), v.y()));
  return p;
}

// Area and perimeter of the overlap of two convex polygons, exactly (CGAL Boolean set
// operations).
std::pair<double, double> overlap_area_perimeter(const std::vector<Vec3>& lower, const std::vector<Vec3>& upper) {
  std::vector<CGAL::Polygon_with_holes_2<Exact>> parts;
  CGAL::intersection(exact_polygon(lower), exact_polygon(upper), std::back_inserter(parts));
  Exact::FT area = 0;
  double perimeter = 0;
  for (const auto& part : parts) {
    area += part.outer_boundary().area();
    for (auto e = part.outer_boundary().edges_begin(); e != part.outer_boundary().edges_end(); ++e)
      perimeter += std::sqrt(CGAL::to_double(e->squared_length()));
  }
  return {CGAL::to_double(area), perimeter};
}

bool inside_polygon(const std::vector<Vec3>& polygon, const Vec3& x, double tolerance) {
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 e = polygon[(i + 1) % polygon.size()] - polygon[i];
    const Vec3 to = x - polygon[i];
    if ((e.x() * to.y() - e.y() * to.x()) / e.norm() < -tolerance) return false;  // right of a ccw edge
  }
  return true;
}

// The stated tolerances: a corner within the slack (0.1 of the contact tolerance, here
// 36 um) outside a side plane of the reference face still counts as in (masonry joints
// have corners exactly on each other's edges), so the area may differ from the exact
// overlap by up to slack x perimeter and points may lie up to the slack outside; an
// overlap smaller than the nominal corner area is a corner contact with that area.
TEST(ContactOracle, FaceOnFaceAreaIsTheExactOverlapOfTheFaces) {
  std::mt19937 random(20261123);
  std::uniform_real_distribution<double> offset(-0.3, 0.3), turn(0, 2 * M_PI), depth(1e-6, 1e-4);
  int faces = 0, corners = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    // Lower prism: top face z = 0. Upper prism: bottom face z = -overlap, turned and moved.
    const std::vector<Vec3> lower_face = random_polygon(random), upper_local = random_polygon(random);
    const double overlap = depth(random), angle = turn(random);
    const Vec3 shift(offset(random), offset(random), 0);
    std::vector<Vec3> upper_face;
    for (const Vec3& v : upper_local) upper_face.push_back(Eigen::AngleAxisd(angle, Vec3::UnitZ()) * v + shift);
    const auto [exact, perimeter] = overlap_area_perimeter(lower_face, upper_face);
    if (exact <= 0) continue;
    const PairContacts c = contacts_between(make_prism(lower_face, -0.4, 0.0), make_prism(upper_face, -overlap, 0.5 - overlap));
    ASSERT_FALSE(c.area.empty()) << "trial " << trial;
    const double area_tolerance = c.slack_m * perimeter + 1e-12;
    if (std::abs(exact - c.nominal_area_m2) < area_tolerance) continue;  // either kind is right
    double area = 0;
    for (std::size_t i = 0; i < c.area.size(); ++i) {
      area += c.area[i];
      EXPECT_NEAR(c.normal[i].z(), 1.0, 1e-12) << "trial " << trial;
      EXPECT_NEAR(c.gap[i], -overlap, 1e-12) << "trial " << trial;
      EXPECT_TRUE(inside_polygon(lower_face, c.point[i], c.slack_m + 1e-12) &&
                  inside_polygon(upper_face, c.point[i], c.slack_m + 1e-12))
          << "trial " << trial << ": sub-contact outside the overlap";
    }
    if (exact > c.nominal_area_m2) {
      EXPECT_NEAR(area, exact, area_tolerance) << "trial " << trial;
      ++faces;
    } else {
      EXPECT_NEAR(area, c.nominal_area_m2, 1e-12) << "trial " << trial;
      ++corners;
    }
  }
  EXPECT_GT(faces, 500);
  EXPECT_GT(corners, 10);
}

// The extent along n of the intersection of two convex polyhedra (CGAL's halfspace
// intersection, from a point strictly inside both), and whether x lies in it (+ tolerance).
struct Intersection {
  double extent = 0;
  bool contains(const Vec3& x, double tolerance) const {
    for (const auto& [n, d] : planes)
      if (n.dot(x) - d > tolerance) return false;
    return true;
  }
  std::vector<std::pair<Vec3, double>> planes;  // n . x <= d
};

Intersection intersect(const Polyhedron& a, const Polyhedron& b, const Vec3& inside, const Vec3& n) {
  Intersection result;
  std::vector<Inexact::Plane_3> planes;
  for (const Polyhedron* p : {&a, &b})
    for (const auto& face : p->faces) {
      const Vec3 x0 = p->vertices[face[0]], x1 = p->vertices[face[1]], x2 = p->vertices[face[2]];
      const Vec3 normal = (x1 - x0).cross(x2 - x0).normalized();  // outward (counter-clockwise faces)
      result.planes.push_back({normal, normal.dot(x0)});
      planes.emplace_back(normal.x(), normal.y(), normal.z(), -normal.dot(x0));
    }
  CGAL::Surface_mesh<Inexact::Point_3> mesh;
  CGAL::halfspace_intersection_3(planes.begin(), planes.end(), mesh, Inexact::Point_3(inside.x(), inside.y(), inside.z()));
  double lo = 1e300, hi = -1e300;
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const double s = n.dot(Vec3(p.x(), p.y(), p.z()));
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  result.extent = hi - lo;
  return result;
}

TEST(ContactOracle, CornerEdgeAndFaceFirstDepthIsTheIntersectionsExtent) {
  std::mt19937 random(1123);
  std::uniform_real_distribution<double> coordinate(-0.25, 0.25), depth(1e-5, 1e-3), unit(-1, 1);
  const Polyhedron base = make_box(Vec3(0, 0, -0.5), Vec3(2, 2, 1));  // top face z = 0, wide
  int tested = 0, corners = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Vec3> points(8 + random() % 12);
    for (Vec3& p : points) p = Vec3(coordinate(random), coordinate(random), coordinate(random));
    const Eigen::Quaterniond turn = Eigen::Quaterniond(unit(random), unit(random), unit(random), unit(random)).normalized();
    Polyhedron stone = transformed(convex_hull(points), turn.toRotationMatrix(), Vec3::Zero());
    double lowest = 1e300;
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& v : stone.vertices) lowest = std::min(lowest, v.z()), centroid += v / stone.vertices.size();
    const double overlap = depth(random);
    stone = transformed(stone, Mat3::Identity(), Vec3(0, 0, -lowest - overlap));
    centroid.z() += -lowest - overlap;
    // A point strictly inside both: from the lowest vertex toward the centroid, to half the overlap.
    Vec3 tip = stone.vertices[0];
    for (const Vec3& v : stone.vertices)
      if (v.z() < tip.z()) tip = v;
    const Vec3 inside = tip + (0.5 * overlap / (centroid.z() - tip.z())) * (centroid - tip);

    const PairContacts c = contacts_between(base, stone);
    ASSERT_FALSE(c.gap.empty()) << "trial " << trial << ", overlap " << overlap << ", tip " << tip.transpose()
                                << ", vertices " << stone.vertices.size();
    const Intersection exact = intersect(base, stone, inside, Vec3::UnitZ());
    for (std::size_t i = 0; i < c.gap.size(); ++i) {
      EXPECT_NEAR(c.normal[i].z(), 1.0, 1e-9) << "trial " << trial;  // the base's face
      EXPECT_TRUE(exact.contains(c.point[i], 1e-9 + overlap)) << "trial " << trial;
    }
    double deepest = 0;
    for (double g : c.gap) deepest = std::min(deepest, g);
    EXPECT_NEAR(-deepest, exact.extent, 1e-9) << "trial " << trial;
    EXPECT_NEAR(exact.extent, overlap, 1e-9) << "trial " << trial;  // the oracle itself
    corners += c.gap.size() == 1;
    ++tested;
  }
  EXPECT_EQ(tested, 300);
  EXPECT_GT(corners, 200);  // random turns put a single corner first
}

}  // namespace
}  // namespace ishibashi
