// Narrowphase, stage 1 (separating_axis.cpp), its empty face pairs: a face pair whose
// manifold came out empty is not clipped again while its stone is clear of the face, by an
// allowance spent step by step (Pair::clear_for_m).
// A cracked bridge has thousands of stones that meet at an edge a fraction of the tolerance
// off each other's face planes; clipping them every step was a quarter of its late step.
#include <algorithm>
#include <cmath>

#include "engine/narrowphase.h"

namespace ishibashi {
namespace {

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

}  // namespace

// The best of the lines: the face's sides and the stone's.
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

// Along the line that held the stone at the last clip. Only the stone's vertices and the
// face's corners are put in the world (a clip puts both blocks' vertices and directions).
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

bool no_closed_point(const Model& m, const State& s, PairWorld& w, const Pair& pair) {
  w.set(m, s, pair.a, pair.b);
  thread_local Manifold manifold;
  face_manifold(m, s, w, pair.a, pair.b, Axis{0.0, pair.axis_kind, pair.axis_feature, face_axis_normal(s, pair.axis_kind, pair.axis_feature)}, manifold);
  for (const ManifoldPoint& q : manifold.points)
    if (q.gap_m <= 0) return false;
  return true;
}

}  // namespace ishibashi
