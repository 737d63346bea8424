// Narrowphase, stage 2: the contact manifold of a touching pair. Face-face and edge-face
// contacts clip the incident face against the reference face (Sutherland-Hodgman), which
// gives the exact overlap polygon; corner and edge-edge contacts get one point with a
// nominal area (Model::point_contact_area_m2).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "engine/narrowphase.h"

namespace ishibashi {
namespace {

// Clipping a convex polygon of n corners by one plane keeps at most n + 2 (two crossings;
// the slack can keep a corner just outside). The incident face's corners plus two per
// side plane of the reference face and two for the tolerance plane stay below this for
// faces of at most kMaxFaceCorners (checked when a block is added, model.cpp).
constexpr int kMaxPolygon = 3 * kMaxFaceCorners + 4;

struct ClipPoint {
  Vec3 x;
  std::uint32_t feature;  // incident vertex id, or a mix of the features that made it
};

struct Polygon {
  int n = 0;
  ClipPoint p[kMaxPolygon];
  void push(const ClipPoint& q) {
    if (n == kMaxPolygon) {  // unreachable for faces within kMaxFaceCorners: never drop a point silently
      std::fprintf(stderr, "ishibashi: internal error: a contact polygon exceeded %d corners\n", kMaxPolygon);
      std::abort();
    }
    p[n++] = q;
  }
};

// Feature id of a point made by cutting segment (p, q) with plane `plane`; order-free.
std::uint32_t crossing_feature(std::uint32_t plane, std::uint32_t fp, std::uint32_t fq) {
  const std::uint32_t lo = std::min(fp, fq), hi = std::max(fp, fq);
  std::uint32_t h = lo * 2654435761u ^ (hi + 0x9e3779b9u + (lo << 6) + (lo >> 2)) * 2246822519u ^ plane * 3266489917u;
  return h | 0x80000000u;  // top bit: a crossing, never an incident vertex id
}

// Keeps the part of `in` where normal . x - offset <= 0. A point within `slack` outside
// counts as inside: masonry joints have corners exactly on each other's edges, and a
// vibration must not make a corner flicker between a vertex and a pair of cuts (new
// keys; near-parallel edges would put the cuts anywhere along the edge).
// A polygon of two points is a segment (faces touching along a line: stones of two courses
// whose plan outlines meet at an edge) and has one edge, not two: cut from both ends, its
// crossing came out twice: a second sub-contact on the same spot, so that end carried two
// thirds of the edge contact's nominal area and the other a third (model F: 2,397 of
// 46,777 sub-contacts).
void clip(const Polygon& in, const Vec3& normal, double offset, double slack, std::uint32_t plane, Polygon& out) {
  out.n = 0;
  const int edges = in.n == 2 ? 1 : in.n;
  for (int i = 0; i < in.n; ++i) {
    const ClipPoint& p = in.p[i];
    const ClipPoint& q = in.p[(i + 1) % in.n];
    const double dp = normal.dot(p.x) - offset, dq = normal.dot(q.x) - offset;
    const bool p_in = dp <= slack, q_in = dq <= slack;
    if (p_in) out.push(p);
    // The cut lies on the true plane. When the kept end lies within the slack of it, on
    // either side, that end stands for the cut: a cut next to it would be a second
    // sub-contact on the same spot (a corner exactly on the side plane of an aligned
    // masonry joint), doubling the joint's stiffness there beyond the stability limit.
    if (i < edges && p_in != q_in && std::abs(p_in ? dp : dq) > slack) {
      const double t = dp / (dp - dq);
      if (t > 0.0 && t < 1.0) out.push(ClipPoint{p.x + t * (q.x - p.x), crossing_feature(plane, p.feature, q.feature)});
    }
  }
}

// Closest points of segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection 5.1.9).
void closest_points(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Vec3& c1, Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
  const double denom = a * e - b * b;
  double sc = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double tc = (b * sc + f) / e;
  if (tc < 0.0) {
    tc = 0.0;
    sc = std::clamp(-c / a, 0.0, 1.0);
  } else if (tc > 1.0) {
    tc = 1.0;
    sc = std::clamp((b - c) / a, 0.0, 1.0);
  }
  c1 = p1 + sc * d1;
  c2 = p2 + tc * d2;
}

// The edge of block `b` with direction index `dir` that lies furthest along `axis`
// (sign = +1) or least far (sign = -1).
int extreme_edge(const Model& m, const PairWorld& w, int b, int dir, const Vec3& axis, double sign) {
  int best = -1;
  double best_value = -1e300;
  for (int e = m.edge_begin[b]; e < m.edge_begin[b + 1]; ++e) {
    if (m.edge_direction[e] != dir) continue;
    const double u0 = sign * axis.dot(w.vertex(m.edge_vertex[e][0]));
    const double u1 = sign * axis.dot(w.vertex(m.edge_vertex[e][1]));
    const double value = std::min(u0, u1);
    if (value > best_value) {
      best_value = value;
      best = e;
    }
  }
  return best;
}

std::uint64_t make_key(int kind, int ref_face_local, int inc_face_local, std::uint32_t feature) {
  return (static_cast<std::uint64_t>(kind) << 62) | (static_cast<std::uint64_t>(ref_face_local & 0x3FFF) << 48) |
         (static_cast<std::uint64_t>(inc_face_local & 0xFFFF) << 32) | feature;
}

// Incident face: of the faces around the incident block's deepest vertex along -n, the
// one most anti-parallel to n. (The most anti-parallel face of the whole block may lie
// elsewhere: a corner poking through a face would then find no contact.)
int incident_face(const Model& m, const State& s, const PairWorld& w, int inc, const Vec3& n) {
  int deepest_vertex = m.vertex_begin[inc];
  for (int v = m.vertex_begin[inc]; v < m.vertex_begin[inc + 1]; ++v)
    if (n.dot(w.vertex(v)) < n.dot(w.vertex(deepest_vertex)) - 1e-12) deepest_vertex = v;
  int g = -1;
  double lowest = 2.0;
  for (int h = m.face_begin[inc]; h < m.face_begin[inc + 1]; ++h) {
    const double c = n.dot(s.face_normal_world[h]);
    if (c >= lowest - 1e-12) continue;
    for (int k = m.face_vertex_begin[h]; k < m.face_vertex_begin[h + 1]; ++k)
      if (m.face_vertex[k] == deepest_vertex) {
        lowest = c;
        g = h;
        break;
      }
  }
  return g;
}

// Incident face g of block inc clipped by the side planes of reference face f (normal n,
// offset d), then to what lies within `tol` of f's plane. Clipping ping-pongs between
// the two buffers (swapping pointers, not kilobytes); returns the one holding the result.
const Polygon& clip_incident_face(const Model& m, const PairWorld& w, int inc, int g, int f, const Vec3& n, double d,
                                  double tol, Polygon (&buffers)[2]) {
  Polygon* in = &buffers[0];
  Polygon* cut = &buffers[1];
  in->n = cut->n = 0;
  for (int k = m.face_vertex_begin[g]; k < m.face_vertex_begin[g + 1]; ++k) {
    const int v = m.face_vertex[k];
    in->push(ClipPoint{w.vertex(v), static_cast<std::uint32_t>(v - m.vertex_begin[inc])});
  }
  // Side planes of the reference face (edge direction x normal points outward).
  const int rb = m.face_vertex_begin[f], re = m.face_vertex_begin[f + 1];
  for (int k = rb; k < re; ++k) {
    const Vec3& p = w.vertex(m.face_vertex[k]);
    const Vec3& q = w.vertex(m.face_vertex[k + 1 < re ? k + 1 : rb]);
    const Vec3 side = (q - p).cross(n).normalized();
    clip(*in, side, side.dot(p), 0.1 * tol, static_cast<std::uint32_t>(k - rb + 1), *cut);
    std::swap(in, cut);
    if (in->n == 0) return *in;
  }
  clip(*in, n, d + tol, 0.0, 0xFFu, *cut);  // keep only what lies within the tolerance
  return *cut;
}

// The clipped polygon projected on the reference plane (normal n, offset d), with the gap
// of each corner and the fan triangles from the corners' mean. The incident face runs
// counter-clockwise about its own normal, i.e. about -n.
struct ContactPolygon {
  int n = 0;
  Vec3 x[kMaxPolygon];
  double gap[kMaxPolygon], fan[kMaxPolygon];
  double area = 0.0;
  Vec3 centroid = Vec3::Zero();  // area-weighted sum; / area for the centroid
};

void project(const Polygon& poly, const Vec3& n, double d, ContactPolygon& c) {
  c.n = poly.n;
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < poly.n; ++i) {
    c.gap[i] = n.dot(poly.p[i].x) - d;
    c.x[i] = poly.p[i].x - c.gap[i] * n;
    mean += c.x[i];
  }
  mean /= poly.n;
  c.area = 0.0;
  c.centroid = Vec3::Zero();
  for (int i = 0; i < poly.n; ++i) {
    const Vec3& p = c.x[i];
    const Vec3& q = c.x[(i + 1) % poly.n];
    c.fan[i] = poly.n >= 3 ? -0.5 * (p - mean).cross(q - mean).dot(n) : 0.0;
    c.area += c.fan[i];
    c.centroid += c.fan[i] * (mean + p + q) / 3.0;
  }
}

// What a manifold's points share: the reference normal n, the incident face's plane (unit
// normal ni, offset di) and the pair's key prefix; and how a point is made of a polygon
// corner or of an interior position.
struct PointRule {
  Vec3 n;
  Vec3 ni;
  double di;
  int kind, ref_local, inc_local;
  std::uint64_t key(std::uint32_t feature) const { return make_key(kind, ref_local, inc_local, feature); }
  // Corner i of the polygon, with its own gap and feature key.
  ManifoldPoint corner(const ContactPolygon& c, const Polygon& poly, int i, double area) const {
    return ManifoldPoint{c.x[i] + 0.5 * c.gap[i] * n, c.x[i] + c.gap[i] * n, c.gap[i], area, key(poly.p[i].feature)};
  }
  // A point y inside the polygon (on the reference plane): its gap follows the incident face.
  ManifoldPoint interior(const Vec3& y, double area, std::uint32_t feature) const {
    const double gy = (di - ni.dot(y)) / ni.dot(n);
    return ManifoldPoint{y + 0.5 * gy * n, y + gy * n, gy, area, key(feature)};
  }
};

// A corner or an edge touching the face: its own points, not those the tolerance plane
// cut (they sit at gap = tolerance), sharing the nominal area.
void corner_points(const ContactPolygon& c, const Polygon& poly, const PointRule& rule, double tol, double nominal,
                   Manifold& out) {
  int kept[kMaxPolygon], count = 0, deepest = 0;
  for (int i = 0; i < c.n; ++i) {
    if (c.gap[i] <= 0.5 * tol) kept[count++] = i;
    if (c.gap[i] < c.gap[deepest]) deepest = i;
  }
  if (count == 0) kept[count++] = deepest;
  for (int k = 0; k < count; ++k) out.push(rule.corner(c, poly, kept[k], nominal / count));
}

// The corner rule (subdivision 1): one point per polygon vertex with its tributary half of
// the two fan triangles.
void vertex_points(const ContactPolygon& c, const Polygon& poly, const PointRule& rule, Manifold& out) {
  for (int i = 0; i < c.n; ++i) out.push(rule.corner(c, poly, i, 0.5 * (c.fan[i] + c.fan[(i + c.n - 1) % c.n])));
}

// JointRule::moments: on each fan triangle (area centroid C, corners i and i+1, area A_i)
// the points C, x_i, x_i+1 weigh A_i / 12 and the triangle's centroid 3 A_i / 4, which
// integrates every quadratic exactly (barycentric moments: int l1^2 = A/6, int l1 l2 =
// A/12).
void moment_points(const ContactPolygon& c, const Polygon& poly, const PointRule& rule, Manifold& out) {
  const Vec3 centroid = c.centroid / c.area;
  double fan[kMaxPolygon];  // fan triangle i: centroid, corner i, corner i+1
  for (int i = 0; i < c.n; ++i) fan[i] = -0.5 * (c.x[i] - centroid).cross(c.x[(i + 1) % c.n] - centroid).dot(rule.n);
  double area = 0.0;
  for (int i = 0; i < c.n; ++i) {
    out.push(rule.corner(c, poly, i, (fan[(i + c.n - 1) % c.n] + fan[i]) / 12.0));
    area += fan[i];
  }
  out.push(rule.interior(centroid, area / 12.0, 0x20000000u));
  for (int i = 0; i < c.n; ++i)
    out.push(rule.interior((centroid + c.x[i] + c.x[(i + 1) % c.n]) / 3.0, 0.75 * fan[i], 0x20000000u | (i + 1)));
}

// Subdivision: fan triangles from the area centroid, each cut into level^2 equal
// sub-triangles; a point at each sub-triangle's centroid.
void subdivided_points(const ContactPolygon& c, const PointRule& rule, int level, Manifold& out) {
  const Vec3 centroid = c.centroid / c.area;
  std::uint32_t index = 0;
  for (int i = 0; i < c.n; ++i) {
    const Vec3 e1 = c.x[i] - centroid, e2 = c.x[(i + 1) % c.n] - centroid;
    const double sub_area = -0.5 * e1.cross(e2).dot(rule.n) / (level * level);
    for (int u = 0; u < level; ++u)
      for (int v = 0; u + v < level; ++v)
        for (int down = 0; down < 2; ++down) {
          if (down && u + v > level - 2) continue;
          const double cu = (3.0 * u + 1.0 + down) / (3.0 * level), cv = (3.0 * v + 1.0 + down) / (3.0 * level);
          out.push(rule.interior(centroid + cu * e1 + cv * e2, sub_area, 0x40000000u | index++));
        }
  }
}

}  // namespace

void face_manifold(const Model& m, const State& s, const PairWorld& w, int a, int b, const Axis& axis, Manifold& out) {
  const bool ref_is_a = axis.kind == 0;
  const int ref = ref_is_a ? a : b, inc = ref_is_a ? b : a;
  const int f = axis.feature;
  const Vec3 n = s.face_normal_world[f];  // out of the reference block
  const double d = s.face_offset_world[f];
  const double tol = m.contact_tolerance_m(a, b);
  const int g = incident_face(m, s, w, inc, n);
  Polygon buffers[2];
  const Polygon& poly = clip_incident_face(m, w, inc, g, f, n, d, tol, buffers);
  if (poly.n == 0) return;

  out.normal = face_axis_normal(s, axis.kind, f);
  const double lever_ref = std::abs(d - n.dot(s.position[ref]));
  const double lever_inc = std::abs(n.dot(s.position[inc]) - d);
  out.lever_a_m = ref_is_a ? lever_ref : lever_inc;
  out.lever_b_m = ref_is_a ? lever_inc : lever_ref;
  const PointRule rule{n, s.face_normal_world[g], s.face_offset_world[g], ref_is_a ? 0 : 1, f - m.face_begin[ref],
                       g - m.face_begin[inc]};
  ContactPolygon c;
  project(poly, n, d, c);
  const double nominal = m.point_contact_area_m2(a, b);
  const int level = m.options.subdivision;
  const double incident_cos = -n.dot(s.face_normal_world[g]);
  if (poly.n < 3 || c.area < nominal) return corner_points(c, poly, rule, tol, nominal, out);
  // A face meeting the reference face at a steep angle keeps its corners whatever the rule.
  if (incident_cos < 0.5 || (level == 1 && m.options.joint_rule == JointRule::corners))
    return vertex_points(c, poly, rule, out);
  if (level == 1) return moment_points(c, poly, rule, out);
  subdivided_points(c, rule, level, out);
}

void edge_manifold(const Model& m, const State& s, const PairWorld& w, int a, int b, const Axis& axis, Manifold& out) {
  const int da = m.direction_begin[a] + axis.feature / 65536, db = m.direction_begin[b] + axis.feature % 65536;
  const int ea = extreme_edge(m, w, a, da, axis.normal, +1.0);
  const int eb = extreme_edge(m, w, b, db, axis.normal, -1.0);
  Vec3 ca, cb;
  closest_points(w.vertex(m.edge_vertex[ea][0]), w.vertex(m.edge_vertex[ea][1]),
                 w.vertex(m.edge_vertex[eb][0]), w.vertex(m.edge_vertex[eb][1]), ca, cb);
  const Vec3 x = 0.5 * (ca + cb);
  out.normal = axis.normal;
  out.lever_a_m = std::abs(axis.normal.dot(x - s.position[a]));
  out.lever_b_m = std::abs(axis.normal.dot(s.position[b] - x));
  const std::uint32_t feature = static_cast<std::uint32_t>((ea - m.edge_begin[a]) * 65536 + (eb - m.edge_begin[b]));
  out.push(ManifoldPoint{x, x, axis.separation_m, m.point_contact_area_m2(a, b), make_key(2, 0, 0, feature)});
}

}  // namespace ishibashi
