// The narrowphase's stages and what they pass each other (engine/narrowphase.cpp calls
// them in order): the separating-axis search with hysteresis (separating_axis.cpp), the
// clipped manifold of a touching pair (manifold.cpp) and the contact history carried from
// one manifold to the next (contact_history.cpp). Internal to the engine's step.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

struct Axis {
  double separation_m = -1e300;
  int kind = -1;     // 0: face of a, 1: face of b, 2: edge-edge
  int feature = -1;  // global face index, or direction pair (da * 65536 + db)
  Vec3 normal = Vec3::Zero();  // a -> b
};

// The a -> b normal of a face axis: face f's outward normal when the face is a's
// (kind 0), reversed when it is b's (kind 1).
inline Vec3 face_axis_normal(const State& s, int kind, int f) {
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

// Output of one pair before it joins the sub-contact arrays.
struct ManifoldPoint {
  Vec3 x;          // on the common plane
  Vec3 incident;   // the matching point on the incident face (x + gap/2 n); face contacts
  double gap_m;
  double area_m2;
  std::uint64_t key;
};

// One per thread, reused: its points keep their capacity (the largest manifold so far),
// so that steps do not allocate; it grows rather than drop a point.
struct Manifold {
  Vec3 normal;  // a -> b
  double lever_a_m, lever_b_m;
  std::vector<ManifoldPoint> points;
  Manifold() { points.reserve(4096); }  // polygon corners x subdivision^2, with room to spare
  void clear() { points.clear(); }
  void push(const ManifoldPoint& q) { points.push_back(q); }
  int size() const { return static_cast<int>(points.size()); }
};

// ---- separating_axis.cpp ----
// Chooses the contact axis of a pair (with hysteresis) and builds its manifold. Returns
// false instead when the pair needs no new manifold: it is still apart, or it has barely
// moved since its last axis search and has a face manifold, whose sub-contacts are then
// updated in place (update_in_place), or an empty one whose stone is still clear of the face.
bool pair_manifold(const Model& m, const State& s, Pair& pair, PairWorld& w, Manifold& out);
// Whether the exact motion test would let an apart pair be (its stones cannot have closed
// the gap): what a skipped apart pair must satisfy, asserted on each skip in debug builds.
bool apart_pair_unmoved(const Model& m, const State& s, const Pair& pair);

// ---- empty_face_pairs.cpp ----
// A face pair whose clip came out empty (w set to the pair): how far it may move before it
// is clipped again (Pair::clear_for_m: while its stone stays above the face's plane or
// beside the face, no clip could give it a closed point), and the line that held its stone
// beside the face (Pair::beside_axis).
void keep_clear(const Model& m, const State& s, const PairWorld& w, Pair& pair, double tol);
// Such a pair has moved as far as that allowed: whether its stone is still clear of the
// face, with its allowance renewed.
bool still_clear(const Model& m, const State& s, Pair& pair, double tol);
// Whether a clip of the pair's face axis now would give no closed point (debug checks).
bool no_closed_point(const Model& m, const State& s, PairWorld& w, const Pair& pair);

// ---- manifold.cpp ----
// The manifold of a face axis: the incident face clipped against the reference face, its
// points placed by the model's joint rule (subdivision 1) or one per sub-triangle. Leaves
// `out` empty when nothing lies within the contact tolerance.
void face_manifold(const Model& m, const State& s, const PairWorld& w, int a, int b, const Axis& axis, Manifold& out);
// The one point of an edge-edge axis, with the nominal corner area.
void edge_manifold(const Model& m, const State& s, const PairWorld& w, int a, int b, const Axis& axis, Manifold& out);

// ---- contact_history.cpp ----
// A barely moved face contact keeps its sub-contacts; only their geometry follows the poses.
void update_in_place(State& s, const Pair& pair);
// Writes the new manifold of a pair into `out` from index `first` (growing it when it is
// too short), each point with the history (springs, bond, slip) of its match among the
// pair's current sub-contacts. Returns the energy the re-clip makes (J, Energy::reclip_j).
double append_rebuilt(const Model& m, const State& s, const Pair& pair, const Manifold& manifold, bool first_detection,
                      double dt_s, SubContacts& out, std::size_t first);

}  // namespace ishibashi
