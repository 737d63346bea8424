// Narrowphase, stage 1: the separating-axis test of a candidate pair (faces of a, faces
// of b, edge-edge directions), with hysteresis so that a resting joint keeps its axis and
// its keys, and a cheap test that skips the search for pairs that barely moved.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "engine/narrowphase.h"

namespace ishibashi {
namespace {

// Largest signed distance of block `other`'s vertices from the plane of face f, negated:
// the separation along the face's normal (> 0: separated).
double face_separation(const Model& m, const State& s, const PairWorld& w, int f, int other) {
  const Vec3& n = s.face_normal_world[f];
  double lowest = 1e300;
  for (int v = m.vertex_begin[other]; v < m.vertex_begin[other + 1]; ++v)
    lowest = std::min(lowest, n.dot(w.vertex(v)));
  return lowest - s.face_offset_world[f];
}

// Whether a face axis (its separation, and how squarely its a -> b normal faces from a's
// centre to b's: the cosine) beats `best`. Faces that separate the blocks equally, within
// `tie_m`, go by the cosine: two stones meeting along an edge touch four planes at once
// (each one's top or bottom and its side), and the normal must come from the geometry,
// not from which stone is a or from a block's face order. A tie in both (a joint's two
// coplanar faces) keeps `best`.
bool beats(double separation_m, double facing, const Axis& best, double best_facing, double tie_m) {
  if (std::abs(separation_m - best.separation_m) > tie_m) return separation_m > best.separation_m;
  return facing > best_facing + 1e-9;
}

// The best face axis among the faces of `owner` (a for kind 0, b for kind 1); `centres` is
// the unit vector from a's centre to b's.
Axis best_face_axis(const Model& m, const State& s, const PairWorld& w, int owner, int other, int kind,
                    const Vec3& centres, double tie_m) {
  Axis best;  // separation -1e300: the first face beats it
  double best_facing = -2;
  const double sign = kind == 0 ? 1.0 : -1.0;  // a -> b normal
  for (int f = m.face_begin[owner]; f < m.face_begin[owner + 1]; ++f) {
    const double sep = face_separation(m, s, w, f, other);
    const double facing = sign * s.face_normal_world[f].dot(centres);
    if (beats(sep, facing, best, best_facing, tie_m)) {
      best = Axis{sep, kind, f, sign * s.face_normal_world[f]};
      best_facing = facing;
    }
  }
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

// How far b moved relative to a since the pair's last axis search: its centroid by
// |offset - offset_at_search| in a's frame, and its turn by angle t moves a point at
// distance r by the chord 2 sin(t/2) r, at most at b's radius (the measure is their sum).
// Also returns the current relative pose, to be stored when the search is redone.
struct MotionSquared {
  double shift2, chord2;  // m^2
};
MotionSquared motion_since_search(const Model& m, const State& s, const Pair& pair, Vec3& offset, Quat& relative) {
  offset = s.rotation[pair.a].transpose() * (s.position[pair.b] - s.position[pair.a]);
  relative = s.orientation[pair.a].conjugate() * s.orientation[pair.b];
  const double shift2 = (offset - pair.offset_at_search).squaredNorm();
  // sin^2(t/2) = 1 - c^2, c the scalar part of the turn q0* q, i.e. the 4-d dot q0 . q.
  const double cos_half_turn = pair.relative_at_search.coeffs().dot(relative.coeffs());
  const double sin2_half_turn = std::max(0.0, 1.0 - cos_half_turn * cos_half_turn);
  return {shift2, 4.0 * sin2_half_turn * m.radius_m[pair.b] * m.radius_m[pair.b]};
}

// Whether any point of block b can have moved relative to block a by `limit_m` or more
// since the pair's last axis search. Most pairs are decided without a square root
// (u + v <= sqrt(2 (u^2 + v^2))). Sets the pair's bound to the measure found when it is
// below the limit.
bool moved_exactly(const Model& m, const State& s, Pair& pair, double limit_m, Vec3& offset, Quat& relative) {
  const auto [shift2, chord2] = motion_since_search(m, s, pair, offset, relative);
  if (limit_m <= 0) return true;
  if (2.0 * (shift2 + chord2) < limit_m * limit_m) {
    pair.moved_bound_m = std::sqrt(2.0 * (shift2 + chord2));
    return false;
  }
  const double measure = std::sqrt(shift2) + std::sqrt(chord2);
  pair.moved_bound_m = measure;
  return measure >= limit_m;
}

// The same answer, most steps without the exact test: the pair's bound on that measure
// grows by this step's motions (pose.cpp). b's centroid moved relative to a's by at most
// |shift_b - shift_a| (its 1-norm: no root), and a's turn by t moves a's frame under a
// point at distance |d| <= |offset_at_search| + limit by t |d|; a point of b at r_b from
// its centre turns relative to a by at most (t_a + t_b) r_b. While the bound stays below
// the limit by more than the exact test's rounding (its chord's root of a difference near
// 1: below 1e-7 r), the answer is no; else the exact test decides and resets the bound.
// A shaken bridge moves its stones together: most pairs skip the exact test for hundreds
// of steps (its rotation, quaternion product and roots: a fifth of a cracked bridge's step).
// `step_m`: what this step adds, a bound on how far any point of b moved relative to a in
// it (inf when the limit is 0).
bool moved_at_least(const Model& m, const State& s, Pair& pair, double limit_m, Vec3& offset, Quat& relative,
                    double& step_m) {
  step_m = std::numeric_limits<double>::infinity();
  if (limit_m > 0) {
    const int a = pair.a, b = pair.b;
    const double rb = m.radius_m[b];
    const double lever = pair.centre_distance_at_search_m + limit_m;
    step_m = (s.step_shift[b] - s.step_shift[a]).cwiseAbs().sum() + s.step_turn[a] * (lever + rb) +
             s.step_turn[b] * rb + 1e-13;
    const double grown = pair.moved_bound_m + step_m;
    const double margin = 1e-6 * (limit_m + rb + lever);
    if (grown < limit_m - margin) {
#ifndef NDEBUG  // the skip gives the exact test's answer, and the bound covers its measure
      Pair exact = pair;
      assert(!moved_exactly(m, s, exact, limit_m, offset, relative));
      const double c = pair.relative_at_search.coeffs().dot(relative.coeffs());
      assert((offset - pair.offset_at_search).norm() + 2.0 * rb * std::sqrt(std::max(0.0, 1.0 - c * c)) <= grown + margin);
#endif
      pair.moved_bound_m = grown;
      return false;
    }
  }
  return moved_exactly(m, s, pair, limit_m, offset, relative);
}

// Where the stone of an empty face pair (its incident block) lies against the reference
// face: its height above the face's plane, and its gap beside the face along a line in the
// plane. The clip keeps only what lies within each side plane of the face moved out by the
// clip's slack, 0.1 tolerance (manifold.cpp, clip_incident_face), so a line with the
// stone's outline on one side and the widened face on the other leaves it nothing,
// whatever its incident face. The lines (axes): the face's sides (k < the face's corners)
// and the stone's edge directions crossed with the face's normal (corners + j), which
// separate any such outline from the face when anything does; the best gap of the axes
// [first_axis, end_axis) is returned. `vertex(v)` and `direction(d)` give the model's
// vertex v and direction d in the world.
struct StoneAgainstFace {
  double height_m;      // its lowest vertex above the face's plane
  double gap_m = -1.0;  // beside the face along `axis`; <= 0: no line separates them
  int axis = -1;
  double rho2;  // m^2: its farthest vertex from b's centre, squared (the lever of kind 1)
};
template <class VertexAt, class DirectionAt>
StoneAgainstFace stone_against_face(const Model& m, const State& s, const Pair& pair, double tol, int first_axis,
                                    int end_axis, VertexAt vertex, DirectionAt direction) {
  const int f = pair.axis_feature, stone = pair.axis_kind == 0 ? pair.b : pair.a;
  const Vec3& n = s.face_normal_world[f];
  const double slack = 0.1 * tol;
  const int first = m.face_vertex_begin[f], corners = m.face_vertex_begin[f + 1] - first;
  StoneAgainstFace at{1e300, -1.0, -1, 0.0};
  for (int v = m.vertex_begin[stone]; v < m.vertex_begin[stone + 1]; ++v) {
    const Vec3 x = vertex(v);
    at.height_m = std::min(at.height_m, n.dot(x));
    at.rho2 = std::max(at.rho2, (x - s.position[pair.b]).squaredNorm());
  }
  at.height_m -= s.face_offset_world[f];
  if (first_axis >= end_axis) return at;
  Vec3 corner[kMaxFaceCorners], side[kMaxFaceCorners], wide[kMaxFaceCorners];
  for (int k = 0; k < corners; ++k) corner[k] = vertex(m.face_vertex[first + k]);
  for (int k = 0; k < corners; ++k) side[k] = (corner[(k + 1) % corners] - corner[k]).cross(n).normalized();
  // The widened face's corners: each moved out by the slack along both sides that meet
  // there, to where the two moved side lines cross (made for the stone's lines only).
  bool widened = false;
  for (int k = 0; k < corners && end_axis > corners; ++k) {
    const Vec3& before = side[(k + corners - 1) % corners];
    const double spread = 1.0 + before.dot(side[k]);  // 1 - cos of the corner's angle
    if (spread < 1e-6) break;                         // (a needle of a corner: those lines are not tried)
    wide[k] = corner[k] + slack / spread * (before + side[k]);
    widened = k == corners - 1;
  }
  for (int axis = first_axis; axis < end_axis; ++axis) {
    double gap = -1.0;
    auto extent = [&](const Vec3& u, double& lo, double& hi) {
      lo = 1e300, hi = -1e300;
      for (int v = m.vertex_begin[stone]; v < m.vertex_begin[stone + 1]; ++v) {
        const double x = u.dot(vertex(v));
        lo = std::min(lo, x), hi = std::max(hi, x);
      }
    };
    double lo, hi;
    if (axis < corners) {
      extent(side[axis], lo, hi);
      gap = lo - side[axis].dot(corner[axis]) - slack;
    } else if (widened) {
      Vec3 u = n.cross(direction(m.direction_begin[stone] + axis - corners));
      const double length = u.norm();
      if (length < 1e-6) continue;  // an edge along the normal: no line of its own
      u /= length;
      double face_lo = 1e300, face_hi = -1e300;
      for (int k = 0; k < corners; ++k) face_lo = std::min(face_lo, u.dot(wide[k])), face_hi = std::max(face_hi, u.dot(wide[k]));
      extent(u, lo, hi);
      gap = std::max(lo - face_hi, face_lo - hi);
    }
    if (gap > at.gap_m) at.gap_m = gap, at.axis = axis;
  }
  return at;
}

// How far the stone may still move relative to the face (as moved_at_least bounds the
// pair's motion step by step) while a clip gives no closed point, by either of two rules:
// * Above the plane: every point of the stone stays above the reference face's plane, so
//   a clip could give only open points, and a new point is never bonded: it would carry
//   no force. The reserve, a tenth of the tolerance, is twice the search's limit: from a
//   skipped step to the pair's next search the stone moves by at most two measures since
//   the search, each below the limit, so it stays above the plane until then, when this
//   code and one that clips every step both clip the pair afresh.
// * Beside the face: a clip would give nothing at all (no reserve: rounding only, 1e-15 of
//   coordinates of tens of metres).
// A point of b moves relative to a by at most the pair's motion (kind 0); a point of a
// relative to b's face by at most its motion times rho / r_b, rho its distance from b's
// centre (kind 1).
double clear_for(const Model& m, const Pair& pair, const StoneAgainstFace& at, double tol) {
  const double lever =
      pair.axis_kind == 1 ? std::max(1.0, (std::sqrt(at.rho2) + std::max(at.height_m, at.gap_m)) / m.radius_m[pair.b]) : 1.0;
  return std::max(at.height_m / lever - 0.1 * tol, at.gap_m / lever - 1e-6 * tol);
}

// A face pair whose manifold came out empty: how far it may move before it is clipped
// again (Pair::clear_for_m), and the line that held its stone beside the face, the best
// of them (Pair::beside_axis). A cracked bridge has thousands of stones that meet at an
// edge a fraction of the tolerance off each other's face planes; clipping them every step
// was a quarter of its late step.
void keep_clear(const Model& m, const State& s, const PairWorld& w, Pair& pair, double tol) {
  const int stone = pair.axis_kind == 0 ? pair.b : pair.a;
  const int axes = m.face_vertex_begin[pair.axis_feature + 1] - m.face_vertex_begin[pair.axis_feature] +
                   m.direction_begin[stone + 1] - m.direction_begin[stone];
  const StoneAgainstFace at = stone_against_face(
      m, s, pair, tol, 0, axes, [&](int v) -> const Vec3& { return w.vertex(v); },
      [&](int d) -> const Vec3& { return w.direction(d); });
  pair.beside_axis = at.gap_m > 0 ? at.axis : -1;
  pair.clear_for_m = std::max(0.0, clear_for(m, pair, at, tol));
}

// The pair has moved as far as its last clip or check allowed: whether its stone is still
// above the plane or beside the face (along the line that held it), and for how far now.
// Only the stone's vertices and the face's corners are put in the world (a clip puts both
// blocks' vertices and directions there).
bool still_clear(const Model& m, const State& s, Pair& pair, double tol) {
  const int a = pair.a, b = pair.b, stone = pair.axis_kind == 0 ? b : a;
  auto vertex = [&](int v) -> Vec3 {
    const int block = v >= m.vertex_begin[a] && v < m.vertex_begin[a + 1] ? a : b;
    return s.position[block] + s.rotation[block] * m.vertex_local[v];
  };
  auto direction = [&](int d) -> Vec3 { return s.rotation[stone] * m.direction_local[d]; };
  const int line = pair.beside_axis;
  pair.clear_for_m = clear_for(m, pair, stone_against_face(m, s, pair, tol, line, line + (line >= 0), vertex, direction), tol);
  return pair.clear_for_m > 0;
}

[[maybe_unused]] bool no_closed_point(const Model& m, const State& s, PairWorld& w, const Pair& pair) {
  w.set(m, s, pair.a, pair.b);
  thread_local Manifold manifold;
  face_manifold(m, s, w, pair.a, pair.b, Axis{0.0, pair.axis_kind, pair.axis_feature, face_axis_normal(s, pair.axis_kind, pair.axis_feature)}, manifold);
  for (const ManifoldPoint& q : manifold.points)
    if (q.gap_m <= 0) return false;
  return true;
}

}  // namespace

bool pair_manifold(const Model& m, const State& s, Pair& pair, PairWorld& w, Manifold& out) {
  out.clear();
  const int a = pair.a, b = pair.b;
  const double tol = m.contact_tolerance_m(a, b);
  Vec3 offset = Vec3::Zero();  // set when the pair has moved (moved_at_least)
  Quat relative = Quat::Identity();
  const bool face_axis = pair.axis_kind == 0 || pair.axis_kind == 1;
  // Still apart: b cannot have closed the gap (separation beyond the tolerance).
  // Barely moved: within a twentieth of the tolerance the clipped features cannot change.
  const double limit = pair.axis_kind == -1 ? pair.separation_m - tol : face_axis ? 0.05 * tol : 0.0;
  double step_m;  // how far b's points moved relative to a in this step, at most
  const bool moved = moved_at_least(m, s, pair, limit, offset, relative, step_m);
  // Damping::capped sets its caps from every sub-contact's springs, open ones too.
  const bool skips_clear = m.options.damping != Damping::capped;
  if (pair.axis_kind == -1 && !moved) return false;
  if (face_axis && !moved) {
    // The last face axis still holds (a resting joint is decided once).
    if (pair.sub_count > 0) return false;
    // An empty manifold: not clipped again while its stone is clear of the face (keep_clear),
    // and checked again (still_clear) when it has moved as far as that allowed.
    if (pair.clear_for_m > 0 && ((pair.clear_for_m -= step_m) > 0 || still_clear(m, s, pair, tol))) {
      assert(no_closed_point(m, s, w, pair));
      return false;
    }
    const int f = pair.axis_feature;
    const Axis cached{0.0, pair.axis_kind, f, face_axis_normal(s, pair.axis_kind, f)};
    w.set(m, s, a, b);
    face_manifold(m, s, w, a, b, cached, out);
    pair.clear_for_m = 0.0;
    pair.beside_axis = -1;
    if (out.size() == 0 && skips_clear) keep_clear(m, s, w, pair, tol);
    return true;
  }
  pair.offset_at_search = offset;
  pair.relative_at_search = relative;
  pair.centre_distance_at_search_m = offset.norm();
  pair.moved_bound_m = 0.0;
  pair.clear_for_m = 0.0;
  pair.beside_axis = -1;
  auto apart = [&](double separation) {
    pair.axis_kind = -1;
    pair.separation_m = separation;
  };

  const double centre_gap = (s.position[a] - s.position[b]).norm() - m.radius_m[a] - m.radius_m[b];
  if (centre_gap > tol) return apart(centre_gap), true;
  w.set(m, s, a, b);
  const double tie = 1e-3 * tol;
  const Vec3 centres = (s.position[b] - s.position[a]).normalized();
  const Axis face_a = best_face_axis(m, s, w, a, b, 0, centres, tie);
  if (face_a.separation_m > tol) return apart(face_a.separation_m), true;
  const Axis face_b = best_face_axis(m, s, w, b, a, 1, centres, tie);
  if (face_b.separation_m > tol) return apart(face_b.separation_m), true;
  const Axis edge = best_edge_axis(m, w, a, b);
  if (edge.separation_m > tol) return apart(edge.separation_m), true;

  // Of a's face and b's, the better (beats); last step's face over both unless clearly
  // worse: exactly touching faces tie, and a flip would change every key.
  const double bias = 0.1 * tol;
  Axis face = beats(face_b.separation_m, face_b.normal.dot(centres), face_a, face_a.normal.dot(centres), tie) ? face_b : face_a;
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
  else {
    face_manifold(m, s, w, a, b, chosen, out);
    if (out.size() == 0 && skips_clear) keep_clear(m, s, w, pair, tol);
  }
  return true;
}


}  // namespace ishibashi
