#include "geometry/validate.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Convex_hull_3/dual/halfspace_intersection_3.h>
#include <CGAL/Convex_hull_3/dual/halfspace_intersection_interior_point_3.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/model.h"

namespace ishibashi {
namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Epick::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string where(const Polyhedron& p) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& v : p.vertices) c += v;
  c /= static_cast<double>(p.vertices.size());
  std::ostringstream s;
  s.precision(4);
  s << " at (" << c.x() << ", " << c.y() << ", " << c.z() << ")";
  return s.str();
}

// Outward planes n . x <= d of a convex block's faces (Newell normals).
struct Plane {
  Vec3 n;
  double d;
};
std::vector<Plane> planes_of(const Polyhedron& p) {
  std::vector<Plane> out;
  for (const auto& f : p.faces) {
    Vec3 n = Vec3::Zero();
    for (std::size_t k = 0; k < f.size(); ++k) n += p.vertices[f[k]].cross(p.vertices[f[(k + 1) % f.size()]]);
    n.normalize();
    out.push_back(Plane{n, n.dot(p.vertices[f[0]])});
  }
  return out;
}

// Whether every vertex of block `b` lies outside one of `a`'s faces moved inwards by
// `shrink`: then no point is strictly inside both shrunk blocks (b is the hull of its
// vertices). Touching stones are separated so by their joint's plane, and this test spares
// them the exact linear program below, 70 % of building model F. (Round-off here is 1e-16 m
// against a 1e-6 m shrink: a pair it wrongly passed would overlap by a film far below any
// tolerance, which overlap_volume returns as 0 as well.)
bool separated_by_a_face(const std::vector<Plane>& a, const Polyhedron& b, double shrink) {
  for (const Plane& p : a) {
    bool outside = true;
    for (const Vec3& v : b.vertices) outside = outside && p.n.dot(v) >= p.d - shrink;
    if (outside) return true;
  }
  return false;
}

// Volume common to two convex blocks: CGAL finds a point strictly inside both (a small
// linear program) and intersects the half-spaces of all faces. Every face is first moved
// inwards by `shrink`, so blocks that only touch (zero-thickness joints, round-off
// included) have no common interior at all.
double overlap_volume(const Polyhedron& pa, const std::vector<Plane>& a, const Polyhedron& pb, const std::vector<Plane>& b,
                      double shrink) {
  if (separated_by_a_face(a, pb, shrink) || separated_by_a_face(b, pa, shrink)) return 0.0;
  std::vector<Epick::Plane_3> planes;
  for (const auto* set : {&a, &b})
    for (const Plane& p : *set) planes.emplace_back(p.n.x(), p.n.y(), p.n.z(), -(p.d - shrink));  // n.x - d' <= 0
  const auto inside = CGAL::halfspace_intersection_interior_point_3(planes.begin(), planes.end());
  if (!inside) return 0.0;
  const Vec3 x(inside->x(), inside->y(), inside->z());
  for (const auto* set : {&a, &b})
    for (const Plane& p : *set)
      if (p.n.dot(x) - (p.d - shrink) > -1e-3 * shrink) return 0.0;  // too thin to build
  CGAL::Polyhedron_3<Epick> common;
  CGAL::halfspace_intersection_3(planes.begin(), planes.end(), common, inside);
  if (common.size_of_vertices() < 4) return 0.0;
  Mesh mesh;
  CGAL::copy_face_graph(common, mesh);
  PMP::triangulate_faces(mesh);
  return std::abs(PMP::volume(mesh));
}

// Area common to two coplanar faces with opposite normals (0 if they are not).
double shared_face_area(const Polyhedron& pa, const std::vector<int>& fa, const Plane& qa, const Polyhedron& pb,
                        const std::vector<int>& fb, const Plane& qb, double eps) {
  if (qa.n.dot(qb.n) > -1 + 1e-9 || std::abs(qa.d + qb.d) > eps) return 0.0;
  const Vec3 u = qa.n.unitOrthogonal(), w = qa.n.cross(u);
  auto project = [&](const Polyhedron& p, const std::vector<int>& f) {
    CGAL::Polygon_2<Epeck> poly;
    for (int v : f) poly.push_back(Epeck::Point_2(u.dot(p.vertices[v]), w.dot(p.vertices[v])));
    if (poly.orientation() == CGAL::CLOCKWISE) poly.reverse_orientation();
    return poly;
  };
  std::vector<CGAL::Polygon_with_holes_2<Epeck>> common;
  CGAL::intersection(project(pa, fa), project(pb, fb), std::back_inserter(common));
  double area = 0;
  for (const auto& c : common) area += CGAL::to_double(c.outer_boundary().area());
  return area;
}

// Why a face is no face of a convex stone, or "": not planar within 1e-4 of the block's
// size, or not a convex polygon (a reflex corner, or an outline that crosses itself). Asked
// before CGAL triangulates the faces, whose triangulation of a crossed outline can crash.
std::string face_fault(const Polyhedron& p, const std::vector<int>& f, double extent) {
  std::vector<Vec3> corners;  // the outline, repeated points dropped
  for (int v : f)
    if (corners.empty() || p.vertices[v] != corners.back()) corners.push_back(p.vertices[v]);
  while (corners.size() > 1 && corners.back() == corners.front()) corners.pop_back();
  Vec3 n = Vec3::Zero(), centre = Vec3::Zero();
  for (std::size_t k = 0; k < corners.size(); ++k) {
    n += corners[k].cross(corners[(k + 1) % corners.size()]);
    centre += corners[k] / static_cast<double>(corners.size());
  }
  std::ostringstream s;
  s.precision(4);
  s << "its face at (" << centre.x() << ", " << centre.y() << ", " << centre.z() << ") ";
  if (corners.size() < 3 || n.norm() < 2e-12 * extent * extent) return s.str() + "has no area (a degenerate face)";
  n.normalize();
  double low = 0, high = 0, turn = 0;
  bool reflex = false;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const double off = n.dot(corners[k] - corners[0]);
    low = std::min(low, off), high = std::max(high, off);
    const Vec3 in = corners[k] - corners[(k + corners.size() - 1) % corners.size()];
    const Vec3 out = corners[(k + 1) % corners.size()] - corners[k];
    const double left = n.dot(in.cross(out));
    reflex = reflex || left < -1e-6 * in.norm() * out.norm();
    turn += std::atan2(left, in.dot(out));
  }
  if (high - low > 1e-4 * extent) {
    s << "is not planar: its corners lie up to " << high - low << " m off one plane; make them coplanar, or split the face into triangles";
    return s.str();
  }
  if (reflex || std::abs(turn - 2 * std::numbers::pi) > 1e-6)
    return s.str() + "is not convex" + (reflex ? " (a corner turns inwards)" : " (its outline crosses itself)") +
           ": a block is one convex stone, each face a convex polygon";
  return "";
}

// Why a block is not a sound convex polyhedron (closed, manifold, outward, no degenerate
// face, its own convex hull); empty when it is, and then `volume` is its volume, m^3.
std::string block_fault(const Polyhedron& p, double& volume) {
  std::vector<Epick::Point_3> points;
  for (const Vec3& v : p.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::vector<std::size_t>> faces;
  for (const auto& f : p.faces) faces.emplace_back(f.begin(), f.end());
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    return "its faces do not form a manifold surface (an edge is shared by more than two faces, or faces disagree in orientation)";
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  if (!CGAL::is_closed(mesh)) return "the surface is open (a hole in it); a block must be a closed polyhedron";
  // The block's size (its box's diagonal, m) scales every tolerance below.
  Vec3 lo = p.vertices[0], hi = lo;
  for (const Vec3& v : p.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double extent = (hi - lo).norm() + 1e-300;
  for (const auto& f : p.faces)
    if (std::string fault = face_fault(p, f, extent); !fault.empty()) return fault;
  PMP::triangulate_faces(mesh);
  bool degenerate = false;
  for (auto f : mesh.faces()) degenerate = degenerate || PMP::face_area(f, mesh) < 1e-12 * extent * extent;
  if (degenerate) return "has a degenerate (zero-area) face";
  volume = PMP::volume(mesh);
  if (volume <= 0 || !PMP::is_outward_oriented(mesh))
    return "faces are inside out (they must be counter-clockwise seen from outside)";
  Mesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  const double hull_volume = PMP::volume(hull);
  if (hull_volume > volume * (1 + 1e-9) + 1e-12 * extent * extent * extent) {
    std::ostringstream s;
    s << "not convex (its volume " << volume << " m^3 is less than its convex hull's " << hull_volume
      << " m^3): a block is one convex stone; cut a concave one into convex pieces, each a closed component of the mesh";
    return s.str();
  }
  return "";
}

}  // namespace

ValidationReport validate_blocks(const std::vector<Polyhedron>& blocks, const std::vector<std::string>& names,
                                 double overlap_tolerance_m3) {
  ValidationReport r;
  r.blocks = static_cast<int>(blocks.size());
  auto label = [&](std::size_t b) {
    std::string s = "block " + std::to_string(b);
    if (b < names.size() && !names[b].empty()) s += " '" + names[b] + "'";
    return s + where(blocks[b]);
  };

  std::vector<char> sound(blocks.size(), 0);
  std::vector<std::vector<Plane>> planes(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    double volume = 0;
    if (const std::string fault = block_fault(blocks[b], volume); !fault.empty()) {
      r.errors.push_back(label(b) + ": " + fault);
      continue;
    }
    r.volume_m3 += volume;
    planes[b] = planes_of(blocks[b]);
    sound[b] = 1;
  }

  // Candidate pairs: bounding boxes that touch or overlap (CGAL's box intersection). An
  // unsound block's box is there too: a block beside it may rest on it, so it is not called
  // floating (its fault is already reported).
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> boxes;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (blocks[b].vertices.empty()) continue;
    Vec3 lo = blocks[b].vertices[0], hi = lo;
    for (const Vec3& v : blocks[b].vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const double pad = 1e-9 * (hi - lo).norm();
    double l[3] = {lo.x() - pad, lo.y() - pad, lo.z() - pad}, h[3] = {hi.x() + pad, hi.y() + pad, hi.z() + pad};
    boxes.emplace_back(l, h, b);
  }
  // Thin tilted blocks side by side (a ring of 100,000 voussoirs) have boxes that overlap
  // thousands of others: the list stops at max_candidate_pairs and the assembly is refused.
  struct TooManyCandidates {};
  const auto limit = static_cast<std::size_t>(max_candidate_pairs(static_cast<long long>(blocks.size())));
  std::vector<std::pair<std::size_t, std::size_t>> candidates;
  try {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
      if (candidates.size() == limit) throw TooManyCandidates{};
      candidates.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
    });
  } catch (const TooManyCandidates&) {
    std::vector<int> partners(blocks.size(), 0);
    for (const auto& [a, b] : candidates) ++partners[a], ++partners[b];
    const std::size_t busiest = std::max_element(partners.begin(), partners.end()) - partners.begin();
    r.errors.push_back("the blocks' bounding boxes overlap in more than " + std::to_string(limit) +
                       " pairs (" + std::to_string(kMaxPairsPerBlock) + " a block; a masonry assembly has about 10): that of " + label(busiest) +
                       " overlaps those of " + std::to_string(partners[busiest]) +
                       " others at least. Blocks far thinner than they are long, side by side, would exhaust the memory: "
                       "make them closer to cubes");
    return r;
  }
  std::sort(candidates.begin(), candidates.end());

  // Round-off allowance for touching faces: a micrometre per metre of the assembly.
  double assembly = 0;
  for (const Box& x : boxes) assembly = std::max(assembly, x.max_coord(0) - x.min_coord(0));
  const double shrink = 1e-6 * std::max(1.0, assembly);
  std::vector<char> touches(blocks.size(), 0);
  for (const auto& [a, b] : candidates) {
    if (!sound[a] || !sound[b]) {
      touches[a] = touches[b] = 1;
      continue;
    }
    const double common = overlap_volume(blocks[a], planes[a], blocks[b], planes[b], shrink);
    if (common > overlap_tolerance_m3) {
      ++r.overlapping_pairs;
      std::ostringstream s;
      s << label(a) << " and " << label(b) << " overlap by " << common << " m^3 (tolerance " << overlap_tolerance_m3 << ")";
      r.errors.push_back(s.str());
      continue;
    }
    const double eps = 1e-9 * (1.0 + std::abs(planes[a][0].d));
    bool shared = false;
    for (std::size_t i = 0; i < planes[a].size() && !shared; ++i)
      for (std::size_t j = 0; j < planes[b].size() && !shared; ++j)
        shared = shared_face_area(blocks[a], blocks[a].faces[i], planes[a][i], blocks[b], blocks[b].faces[j], planes[b][j], eps) > 1e-12;
    if (shared) {
      ++r.shared_faces;
      touches[a] = touches[b] = 1;
    }
  }
  if (blocks.size() > 1)
    for (std::size_t b = 0; b < blocks.size(); ++b)
      if (sound[b] && !touches[b]) r.errors.push_back(label(b) + ": meets no other block on a shared face (it floats)");
  return r;
}

}  // namespace ishibashi
