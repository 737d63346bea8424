// Narrowphase, stage 1: the separating-axis test of a candidate pair (faces of a, faces
// of b, edge-edge directions), with hysteresis so that a resting joint keeps its axis and
// its keys, and a cheap test that skips the search for pairs that barely moved (and the
// clip of empty face pairs whose stones are clear of the face: empty_face_pairs.cpp).
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

// An apart pair that the motion test just let be (`pair.moved_bound_m` below its limit):
// left unvisited while the apart clock (pose.cpp) moves on by less than its slack, the room
// its bound has left below the limit. Every step it is skipped would add at most the clock's
// step to its bound, so the test would answer no in each. Only where the slack outlasts a
// few of the clock's steps: a pair near its limit is cheaper kept on its own bound.
void schedule_apart(const Model& m, const State& s, Pair& pair, double limit_m) {
  if (!s.apart_clock_valid) return;
  const double rb = m.radius_m[pair.b];
  const double lever = pair.centre_distance_at_search_m + limit_m;
  if (lever + 2.0 * rb > m.apart_lever_bound_m) return;
  const double slack = limit_m - 1e-6 * (limit_m + rb + lever) - pair.moved_bound_m;
  if (slack > 8.0 * s.apart_clock_step_m) pair.apart_until_clock_m = s.apart_clock_m + slack;
}

// Back from a skip: the steps skipped are in the clock, not in the pair's bound. Unknown:
// the exact test runs (once a skip, not each step).
void end_apart_skip(Pair& pair) {
  if (pair.apart_until_clock_m == -std::numeric_limits<double>::infinity()) return;
  pair.apart_until_clock_m = -std::numeric_limits<double>::infinity();
  pair.moved_bound_m = std::numeric_limits<double>::infinity();
}

}  // namespace

bool apart_pair_unmoved(const Model& m, const State& s, const Pair& pair) {
  Pair exact = pair;
  Vec3 offset;
  Quat relative;
  return !moved_exactly(m, s, exact, pair.separation_m - m.contact_tolerance_m(pair.a, pair.b), offset, relative);
}

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
  end_apart_skip(pair);
  double step_m;  // how far b's points moved relative to a in this step, at most
  const bool moved = moved_at_least(m, s, pair, limit, offset, relative, step_m);
  // Damping::capped sets its caps from every sub-contact's springs, open ones too.
  const bool skips_clear = m.options.damping != Damping::capped;
  if (pair.axis_kind == -1 && !moved) return schedule_apart(m, s, pair, limit), false;
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
