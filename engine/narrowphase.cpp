// Narrowphase: separating-axis test per candidate pair, then a contact manifold.
// Face-face and edge-face contacts clip the incident face against the reference face
// (Sutherland-Hodgman), which gives the exact overlap polygon; corner and edge-edge
// contacts get one point with a nominal area (Model::point_contact_area_m2).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

constexpr int kMaxPolygon = 64;
constexpr int kMaxManifold = 4096;  // polygon corners x subdivision^2, with room to spare

struct ClipPoint {
  Vec3 x;
  std::uint32_t feature;  // incident vertex id, or a mix of the features that made it
};

struct Polygon {
  int n = 0;
  ClipPoint p[kMaxPolygon];
  void push(const ClipPoint& q) {
    if (n < kMaxPolygon) p[n++] = q;
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
void clip(const Polygon& in, const Vec3& normal, double offset, double slack, std::uint32_t plane, Polygon& out) {
  out.n = 0;
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
    if (p_in != q_in && std::abs(p_in ? dp : dq) > slack) {
      const double t = dp / (dp - dq);
      if (t > 0.0 && t < 1.0) out.push(ClipPoint{p.x + t * (q.x - p.x), crossing_feature(plane, p.feature, q.feature)});
    }
  }
}

struct Axis {
  double separation_m = -1e300;
  int kind = -1;     // 0: face of a, 1: face of b, 2: edge-edge
  int feature = -1;  // global face index, or direction pair (da * 65536 + db)
  Vec3 normal = Vec3::Zero();  // a -> b
};

// The a -> b normal of a face axis: face f's outward normal when the face is a's
// (kind 0), reversed when it is b's (kind 1).
Vec3 face_axis_normal(const State& s, int kind, int f) {
  return kind == 0 ? s.face_normal_world[f] : Vec3(-s.face_normal_world[f]);
}

// World-frame vertices and edge directions of the two blocks of the pair being searched.
// Only the pairs that moved are searched in a step, so these are made here, per pair,
// rather than by the pose stage for every block. One per thread, reused: its buffers grow
// to the largest pair once and are not allocated again.
class PairWorld {
 public:
  void set(const Model& m, const State& s, int a, int b) {
    a_vertices_ = m.vertex_begin[a];
    b_vertices_ = m.vertex_begin[b];
    a_directions_ = m.direction_begin[a];
    b_directions_ = m.direction_begin[b];
    na_vertices_ = m.vertex_begin[a + 1] - a_vertices_;
    na_directions_ = m.direction_begin[a + 1] - a_directions_;
    vertices_.resize(na_vertices_ + m.vertex_begin[b + 1] - b_vertices_);
    directions_.resize(na_directions_ + m.direction_begin[b + 1] - b_directions_);
    for (int v = 0; v < na_vertices_; ++v) vertices_[v] = s.position[a] + s.rotation[a] * m.vertex_local[a_vertices_ + v];
    for (int v = na_vertices_; v < static_cast<int>(vertices_.size()); ++v)
      vertices_[v] = s.position[b] + s.rotation[b] * m.vertex_local[b_vertices_ + v - na_vertices_];
    for (int d = 0; d < na_directions_; ++d) directions_[d] = s.rotation[a] * m.direction_local[a_directions_ + d];
    for (int d = na_directions_; d < static_cast<int>(directions_.size()); ++d)
      directions_[d] = s.rotation[b] * m.direction_local[b_directions_ + d - na_directions_];
  }
  // By the model's global vertex and direction indices (of block a or b).
  const Vec3& vertex(int v) const {
    const bool of_a = v >= a_vertices_ && v < a_vertices_ + na_vertices_;
    return of_a ? vertices_[v - a_vertices_] : vertices_[na_vertices_ + v - b_vertices_];
  }
  const Vec3& direction(int d) const {
    const bool of_a = d >= a_directions_ && d < a_directions_ + na_directions_;
    return of_a ? directions_[d - a_directions_] : directions_[na_directions_ + d - b_directions_];
  }

 private:
  int a_vertices_ = 0, b_vertices_ = 0, na_vertices_ = 0;
  int a_directions_ = 0, b_directions_ = 0, na_directions_ = 0;
  std::vector<Vec3> vertices_, directions_;
};

// Largest signed distance of block `other`'s vertices from the plane of face f, negated:
// the separation along the face's normal (> 0: separated).
double face_separation(const Model& m, const State& s, const PairWorld& w, int f, int other) {
  const Vec3& n = s.face_normal_world[f];
  double lowest = 1e300;
  for (int v = m.vertex_begin[other]; v < m.vertex_begin[other + 1]; ++v)
    lowest = std::min(lowest, n.dot(w.vertex(v)));
  return lowest - s.face_offset_world[f];
}

Axis best_face_axis(const Model& m, const State& s, const PairWorld& w, int owner, int other, int kind) {
  Axis best;
  for (int f = m.face_begin[owner]; f < m.face_begin[owner + 1]; ++f) {
    const double sep = face_separation(m, s, w, f, other);
    if (sep > best.separation_m) best = Axis{sep, kind, f, s.face_normal_world[f]};
  }
  if (kind == 1) best.normal = -best.normal;
  return best;
}

void support_range(const Model& m, const PairWorld& w, int b, const Vec3& axis, double& lo, double& hi) {
  lo = 1e300;
  hi = -1e300;
  for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) {
    const double d = axis.dot(w.vertex(v));
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
}

Axis best_edge_axis(const Model& m, const PairWorld& w, int a, int b) {
  Axis best;
  for (int da = m.direction_begin[a]; da < m.direction_begin[a + 1]; ++da)
    for (int db = m.direction_begin[b]; db < m.direction_begin[b + 1]; ++db) {
      Vec3 axis = w.direction(da).cross(w.direction(db));
      const double len = axis.norm();
      if (len < 1e-6) continue;  // parallel edges: their axis is a face axis or none
      axis /= len;
      double alo, ahi, blo, bhi;
      support_range(m, w, a, axis, alo, ahi);
      support_range(m, w, b, axis, blo, bhi);
      const double forward = blo - ahi, backward = alo - bhi;
      const double sep = std::max(forward, backward);
      if (sep > best.separation_m)
        best = Axis{sep, 2, (da - m.direction_begin[a]) * 65536 + (db - m.direction_begin[b]),
                    forward >= backward ? axis : Vec3(-axis)};
    }
  return best;
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

// Output of one pair before it joins the sub-contact arrays.
struct ManifoldPoint {
  Vec3 x;          // on the common plane
  Vec3 incident;   // the matching point on the incident face (x + gap/2 n); face contacts
  double gap_m;
  double area_m2;
  std::uint64_t key;
};

struct Manifold {
  Vec3 normal;  // a -> b
  double lever_a_m, lever_b_m;
  int n = 0;
  ManifoldPoint p[kMaxManifold];
  void push(const ManifoldPoint& q) {
    if (n < kMaxManifold) p[n++] = q;
  }
};

void face_manifold(const Model& m, const State& s, const PairWorld& w, int a, int b, const Axis& axis, Manifold& out) {
  const bool ref_is_a = axis.kind == 0;
  const int ref = ref_is_a ? a : b, inc = ref_is_a ? b : a;
  const int f = axis.feature;
  const Vec3 n = s.face_normal_world[f];  // out of the reference block
  const double d = s.face_offset_world[f];
  const double tol = m.contact_tolerance_m(a, b);

  // Incident face: of the faces around the incident block's deepest vertex, the one most
  // anti-parallel to the reference normal. (The most anti-parallel face of the whole
  // block may lie elsewhere: a corner poking through a face would then find no contact.)
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
  Polygon buffers[2];  // clipping ping-pongs between the two (swapping pointers, not 2 KB)
  Polygon* in = &buffers[0];
  Polygon* cut = &buffers[1];
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
    if (in->n == 0) return;
  }
  clip(*in, n, d + tol, 0.0, 0xFFu, *cut);  // keep only what lies within the tolerance
  const Polygon& poly = *cut;
  if (poly.n == 0) return;

  out.normal = face_axis_normal(s, axis.kind, f);
  const double lever_ref = std::abs(d - n.dot(s.position[ref]));
  const double lever_inc = std::abs(n.dot(s.position[inc]) - d);
  out.lever_a_m = ref_is_a ? lever_ref : lever_inc;
  out.lever_b_m = ref_is_a ? lever_inc : lever_ref;
  const int ref_local = f - m.face_begin[ref], inc_local = g - m.face_begin[inc];
  const int kind = ref_is_a ? 0 : 1;

  // Polygon projected on the reference plane, with gaps; fan areas from the vertex mean.
  // The incident face runs counter-clockwise about its own normal, i.e. about -n.
  Vec3 x[kMaxPolygon];
  double gap[kMaxPolygon], fan[kMaxPolygon];
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < poly.n; ++i) {
    gap[i] = n.dot(poly.p[i].x) - d;
    x[i] = poly.p[i].x - gap[i] * n;
    mean += x[i];
  }
  mean /= poly.n;
  double area = 0.0;
  Vec3 centroid = Vec3::Zero();
  for (int i = 0; i < poly.n; ++i) {
    const Vec3& p = x[i];
    const Vec3& q = x[(i + 1) % poly.n];
    fan[i] = poly.n >= 3 ? -0.5 * (p - mean).cross(q - mean).dot(n) : 0.0;
    area += fan[i];
    centroid += fan[i] * (mean + p + q) / 3.0;
  }
  const double nominal = m.point_contact_area_m2(a, b);
  const int level = m.contact.subdivision;
  const double incident_cos = -n.dot(s.face_normal_world[g]);

  if (poly.n < 3 || area < nominal) {
    // A corner or an edge touching the face: keep its own points, not those the
    // tolerance plane cut (they sit at gap = tolerance), and give them the nominal area.
    int kept[kMaxPolygon], count = 0, deepest = 0;
    for (int i = 0; i < poly.n; ++i) {
      if (gap[i] <= 0.5 * tol) kept[count++] = i;
      if (gap[i] < gap[deepest]) deepest = i;
    }
    if (count == 0) kept[count++] = deepest;
    for (int k = 0; k < count; ++k) {
      const int i = kept[k];
      out.push(ManifoldPoint{x[i] + 0.5 * gap[i] * n, x[i] + gap[i] * n, gap[i], nominal / count,
                             make_key(kind, ref_local, inc_local, poly.p[i].feature)});
    }
    return;
  }
  if (level == 1 || incident_cos < 0.5) {
    // One point per polygon vertex with its tributary half of the two fan triangles.
    for (int i = 0; i < poly.n; ++i) {
      const double share = 0.5 * (fan[i] + fan[(i + poly.n - 1) % poly.n]);
      out.push(ManifoldPoint{x[i] + 0.5 * gap[i] * n, x[i] + gap[i] * n, gap[i], share,
                             make_key(kind, ref_local, inc_local, poly.p[i].feature)});
    }
    return;
  }
  // Subdivision: fan triangles from the area centroid, each cut into level^2 equal
  // sub-triangles; a point at each sub-triangle's centroid. The gap there follows the
  // incident face's plane.
  centroid /= area;
  const Vec3& ni = s.face_normal_world[g];
  const double di = s.face_offset_world[g];
  auto gap_at = [&](const Vec3& y) { return (di - ni.dot(y)) / ni.dot(n); };
  std::uint32_t index = 0;
  for (int i = 0; i < poly.n; ++i) {
    const Vec3 e1 = x[i] - centroid, e2 = x[(i + 1) % poly.n] - centroid;
    const double sub_area = -0.5 * e1.cross(e2).dot(n) / (level * level);
    for (int u = 0; u < level; ++u)
      for (int v = 0; u + v < level; ++v)
        for (int down = 0; down < 2; ++down) {
          if (down && u + v > level - 2) continue;
          const double cu = (3.0 * u + 1.0 + down) / (3.0 * level), cv = (3.0 * v + 1.0 + down) / (3.0 * level);
          const Vec3 y = centroid + cu * e1 + cv * e2;
          const double gy = gap_at(y);
          out.push(ManifoldPoint{y + 0.5 * gy * n, y + gy * n, gy, sub_area,
                                 make_key(kind, ref_local, inc_local, 0x40000000u | index++)});
        }
  }
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

// Whether any point of block b can have moved relative to block a by `limit_m` or more
// since the pair's last axis search. b's centroid moved by |offset - offset_at_search|
// in a's frame, and a turn by angle t moves a point at distance r by the chord
// 2 sin(t/2) r. Also returns the current relative pose, to be stored when the search is
// redone. Most pairs are decided without a square root (u + v <= sqrt(2 (u^2 + v^2))).
bool moved_at_least(const Model& m, const State& s, const Pair& pair, double limit_m, Vec3& offset, Quat& relative) {
  offset = s.rotation[pair.a].transpose() * (s.position[pair.b] - s.position[pair.a]);
  relative = s.orientation[pair.a].conjugate() * s.orientation[pair.b];
  if (limit_m <= 0) return true;
  const double shift2 = (offset - pair.offset_at_search).squaredNorm();
  // sin^2(t/2) = 1 - c^2, c the scalar part of the turn q0* q, i.e. the 4-d dot q0 . q.
  const double cos_half_turn = pair.relative_at_search.coeffs().dot(relative.coeffs());
  const double sin2_half_turn = std::max(0.0, 1.0 - cos_half_turn * cos_half_turn);
  const double chord2 = 4.0 * sin2_half_turn * m.radius_m[pair.b] * m.radius_m[pair.b];
  if (2.0 * (shift2 + chord2) < limit_m * limit_m) return false;
  return std::sqrt(shift2) + std::sqrt(chord2) >= limit_m;
}

// Chooses the contact axis of a pair (with hysteresis) and builds its manifold. Returns
// false instead when the pair needs no new manifold: it is still apart, or it has barely
// moved since its last axis search and has a face manifold, whose sub-contacts are then
// updated in place (update_in_place).
bool pair_manifold(const Model& m, const State& s, Pair& pair, PairWorld& w, Manifold& out) {
  out.n = 0;
  const int a = pair.a, b = pair.b;
  const double tol = m.contact_tolerance_m(a, b);
  Vec3 offset;
  Quat relative;
  const bool face_axis = pair.axis_kind == 0 || pair.axis_kind == 1;
  // Still apart: b cannot have closed the gap (separation beyond the tolerance).
  // Barely moved: within a twentieth of the tolerance the clipped features cannot change.
  const double limit = pair.axis_kind == -1 ? pair.separation_m - tol : face_axis ? 0.05 * tol : 0.0;
  const bool moved = moved_at_least(m, s, pair, limit, offset, relative);
  if (pair.axis_kind == -1 && !moved) return false;
  if (face_axis && !moved) {
    // The last face axis still holds (a resting joint is decided once).
    if (pair.sub_count > 0) return false;
    const int f = pair.axis_feature;
    const Axis cached{0.0, pair.axis_kind, f, face_axis_normal(s, pair.axis_kind, f)};
    w.set(m, s, a, b);
    face_manifold(m, s, w, a, b, cached, out);
    return true;
  }
  pair.offset_at_search = offset;
  pair.relative_at_search = relative;
  auto apart = [&](double separation) {
    pair.axis_kind = -1;
    pair.separation_m = separation;
  };

  const double centre_gap = (s.position[a] - s.position[b]).norm() - m.radius_m[a] - m.radius_m[b];
  if (centre_gap > tol) return apart(centre_gap), true;
  w.set(m, s, a, b);
  const Axis face_a = best_face_axis(m, s, w, a, b, 0);
  if (face_a.separation_m > tol) return apart(face_a.separation_m), true;
  const Axis face_b = best_face_axis(m, s, w, b, a, 1);
  if (face_b.separation_m > tol) return apart(face_b.separation_m), true;
  const Axis edge = best_edge_axis(m, w, a, b);
  if (edge.separation_m > tol) return apart(edge.separation_m), true;

  // Prefer a face of a over one of b, and last step's face over both, unless clearly
  // worse: exactly touching faces tie, and a flip would change every key.
  const double bias = 0.1 * tol;
  Axis face = face_a.separation_m >= face_b.separation_m - 1e-3 * tol ? face_a : face_b;
  if (pair.axis_kind == 0 || pair.axis_kind == 1) {
    const int f = pair.axis_feature;
    const double sep = face_separation(m, s, w, f, pair.axis_kind == 0 ? b : a);
    if (sep >= face.separation_m - bias)
      face = Axis{sep, pair.axis_kind, f, face_axis_normal(s, pair.axis_kind, f)};
  }
  const Axis& chosen = edge.separation_m > face.separation_m + bias ? edge : face;
  pair.axis_kind = chosen.kind;
  pair.axis_feature = chosen.feature;
  if (chosen.kind == 2)
    edge_manifold(m, s, w, a, b, chosen, out);
  else
    face_manifold(m, s, w, a, b, chosen, out);
  return true;
}

// A barely moved face contact keeps its sub-contacts (keys, areas, levers, springs,
// bond) and only their geometry follows the current poses: the incident point rides on
// its block, the reference face gives the normal and the gap.
void update_in_place(State& s, const Pair& pair) {
  SubContacts& c = s.contacts;
  const int inc = pair.axis_kind == 0 ? pair.b : pair.a;
  const int f = pair.axis_feature;
  const Vec3 n = s.face_normal_world[f];
  const Vec3 normal = face_axis_normal(s, pair.axis_kind, f);
  const double d = s.face_offset_world[f];
  const Mat3& r = s.rotation[inc];
  const Vec3 x = s.position[inc];
  for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
    const Vec3 incident = x + r * c.incident_local[i];
    const double gap = n.dot(incident) - d;
    c.point[i] = incident - 0.5 * gap * n;
    c.normal[i] = normal;
    c.gap_change_m[i] = gap - c.gap_m[i];
    c.gap_m[i] = gap;
  }
}

// Appends the new manifold of a pair to `out`, each point with the history (springs,
// bond, slip) of its match among the pair's current sub-contacts.
void append_rebuilt(const Model& m, const State& s, const Pair& pair, const Manifold& manifold, bool first_detection,
                    double dt_s, SubContacts& out) {
  const SubContacts& old = s.contacts;
  const int old_begin = pair.sub_begin, old_end = pair.sub_begin + pair.sub_count;
  const int incident_block = pair.axis_kind == 1 ? pair.a : pair.b;
  const Mat3 to_incident = s.rotation[incident_block].transpose();
  const PairLaw& law = m.law(m.material[pair.a], m.material[pair.b]);
  const bool bondable = first_detection && (law.tensile_pa > 0 || law.cohesion_pa > 0);
  const double reach = 1e-2 * std::min(m.size_m[pair.a], m.size_m[pair.b]);
  const std::size_t first = out.size();
  out.resize(first + manifold.n);
  for (int i = 0; i < manifold.n; ++i) {
    const ManifoldPoint& p = manifold.p[i];
    const std::size_t j = first + i;
    out.block_a[j] = pair.a;
    out.block_b[j] = pair.b;
    out.key[j] = p.key;
    out.point[j] = p.x;
    out.normal[j] = manifold.normal;
    out.gap_m[j] = p.gap_m;
    out.area_m2[j] = p.area_m2;
    const SpringConstants k = spring_constants(m, pair.a, pair.b, manifold.lever_a_m, manifold.lever_b_m, p.area_m2);
    out.normal_stiffness_n_m[j] = k.kn;
    out.shear_stiffness_n_m[j] = k.ks;
    out.normal_damping_n_s_m[j] = k.cn;
    out.shear_damping_n_s_m[j] = k.cs;
    out.incident_local[j] = to_incident * (p.incident - s.position[incident_block]);
    // A key seen last step keeps its springs and bond. Failing that, the nearest old
    // point of the pair within `reach` passes them on: where corners lie exactly on
    // each other's edges (aligned masonry joints), a vertex and a pair of cuts swap
    // back and forth under round-off-sized motions, and the joint must not forget.
    // Springs pass on as stresses (scaled by the area ratio).
    int found = -1;
    for (int q = old_begin; q < old_end; ++q)
      if (old.key[q] == p.key) {
        found = q;
        break;
      }
    if (found < 0) {
      double best = reach * reach;
      for (int q = old_begin; q < old_end; ++q) {
        const double d2 = (old.point[q] - p.x).squaredNorm();
        if (d2 < best) {
          best = d2;
          found = q;
        }
      }
    }
    if (found >= 0) {
      const double ratio = p.area_m2 / old.area_m2[found];
      out.normal_stretch_m[j] = old.normal_stretch_m[found] * ratio * old.normal_stiffness_n_m[found] / k.kn;
      out.shear_stretch_m[j] = old.shear_stretch_m[found] * (ratio * old.shear_stiffness_n_m[found] / k.ks);
      out.flags[j] = old.flags[found];
      if (!(out.flags[j] & SubContactFlag::bonded))  // a dry point holds no more than its own overlap
        out.normal_stretch_m[j] = std::max(out.normal_stretch_m[j], std::min(p.gap_m, 0.0));
      out.damping_force_n[j] = old.damping_force_n[found] * ratio;
      // The joint's own motion over the last step, not the jump from the old point's gap
      // to the new one's (a new point is not a displacement of the joint).
      const Vec3 va = s.velocity[pair.a] + s.angular_velocity[pair.a].cross(p.x - s.position[pair.a]);
      const Vec3 vb = s.velocity[pair.b] + s.angular_velocity[pair.b].cross(p.x - s.position[pair.b]);
      out.gap_change_m[j] = dt_s * (vb - va).dot(manifold.normal);
      out.slip_m[j] = old.slip_m[found];
    } else {
      out.normal_stretch_m[j] = bondable ? p.gap_m : std::min(p.gap_m, 0.0);  // from its overlap
      out.shear_stretch_m[j] = Vec3::Zero();
      out.flags[j] = (bondable ? SubContactFlag::bonded : 0) | (first_detection ? SubContactFlag::original : 0);
      out.damping_force_n[j] = Vec3::Zero();
      out.gap_change_m[j] = 0.0;
      out.slip_m[j] = 0.0;
    }
  }
  // A re-clipped pair keeps the spring energy it stored: its springs, passed on or new,
  // are scaled together to it. Otherwise a corner contact (small area, soft) that turns
  // into a face contact (large area, stiff) would turn the stresses it passes on into
  // energy from nothing and the stones would pop apart, a face contact that turns into
  // a corner would lose most of its energy, and a pair whose features change while the
  // blocks overlap deeply (a falling stone's corner that turns out to be a face 9 mm
  // inside its neighbour) would start its new points from that overlap: a pair that
  // stored nothing starts with nothing (Nishida A at subdivision 2: balance error 50 %
  // of the energy exchanged before, 0.15 % after).
  double before = 0, after = 0;
  for (int q = old_begin; q < old_end; ++q) before += old.spring_energy(q);
  for (std::size_t j = first; j < out.size(); ++j) after += out.spring_energy(j);
  if (after > 0 && after != before) {
    const double scale = std::sqrt(before / after);
    for (std::size_t j = first; j < out.size(); ++j) {
      out.normal_stretch_m[j] *= scale;
      out.shear_stretch_m[j] *= scale;
    }
  }
}

}  // namespace

// Most pairs of a masonry structure barely move relative to each other from one step to
// the next: their sub-contacts are updated where they lie, and only pairs whose manifold
// is rebuilt go through per-chunk buffers. The arrays are regrouped only when a pair
// gains or loses sub-contacts or the pair list changed.
void update_contacts(const Model& m, State& s, bool first_detection, double dt_s) {
  const int np = static_cast<int>(s.pairs.size());
  const int chunks = kBufferChunks;
  s.chunk_contacts.resize(chunks);
  s.chunk_regroup.assign(chunks, 0);
  parallel_chunks(np, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    SubContacts& out = s.chunk_contacts[k];
    out.clear();
    thread_local Manifold manifold;  // large; one per thread, reused
    thread_local PairWorld world;
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      Pair& pair = s.pairs[pi];
      pair.rebuilt_count = -1;
      if (!pair_manifold(m, s, pair, world, manifold)) {
        if (pair.sub_count > 0) update_in_place(s, pair);
        continue;
      }
      pair.rebuilt_begin = static_cast<int>(out.size());
      pair.rebuilt_count = manifold.n;
      const std::uint8_t change = manifold.n != pair.sub_count ? 2 : manifold.n > 0 ? 1 : 0;
      s.chunk_regroup[k] = std::max(s.chunk_regroup[k], change);
      append_rebuilt(m, s, pair, manifold, first_detection, dt_s, out);
    }
  });
  std::uint8_t change = s.pairs_changed ? 2 : 0;  // 0 none, 1 same layout, 2 regroup
  for (std::uint8_t r : s.chunk_regroup) change = std::max(change, r);
  s.pairs_changed = false;
  if (change == 0) return;  // every pair updated in place (or still apart)

  if (change == 1) {  // same layout: rebuilt pairs overwrite their own ranges
    parallel_chunks(np, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
      for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
        const Pair& pair = s.pairs[pi];
        if (pair.rebuilt_count > 0)
          s.contacts.copy_range(s.chunk_contacts[k], pair.rebuilt_begin, pair.rebuilt_count, pair.sub_begin);
      }
    });
    return;
  }
  ++s.profile.contact_regroups;
  s.pair_scratch_begin.resize(np);
  int total = 0;
  for (int pi = 0; pi < np; ++pi) {
    const Pair& pair = s.pairs[pi];
    s.pair_scratch_begin[pi] = total;
    total += pair.rebuilt_count >= 0 ? pair.rebuilt_count : pair.sub_count;
  }
  s.next_contacts.resize(total);
  parallel_chunks(np, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    // Runs of pairs that kept their sub-contacts are contiguous in both layouts: one
    // copy per run, not one per pair (a regroup typically changes a handful of pairs).
    int run_from = 0, run_to = 0, run_count = 0;
    auto flush = [&] {
      if (run_count > 0) s.next_contacts.copy_range(s.contacts, run_from, run_count, run_to);
      run_count = 0;
    };
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      Pair& pair = s.pairs[pi];
      const int at = s.pair_scratch_begin[pi];
      if (pair.rebuilt_count >= 0) {
        flush();
        s.next_contacts.copy_range(s.chunk_contacts[k], pair.rebuilt_begin, pair.rebuilt_count, at);
        pair.sub_count = pair.rebuilt_count;
      } else if (pair.sub_count > 0) {
        if (run_count == 0) run_from = pair.sub_begin, run_to = at;
        run_count += pair.sub_count;
      }
      pair.sub_begin = at;
    }
    flush();
  });
  std::swap(s.contacts, s.next_contacts);
}

}  // namespace ishibashi
