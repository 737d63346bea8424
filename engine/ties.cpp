// Tie rods (Model::ties): a steel bar between anchor points fixed in two free blocks,
// carrying tension only, elastic up to its yield force and perfectly plastic past it. The
// stage runs serially after the contact law (a bridge has tens of ties, not thousands):
// each tie's force and its moments about the blocks' centroids go to per-tie arrays that
// the gather reads through Model::block_tie, as it reads the pairs', so a block's sum is
// the same for any number of threads.
#include <algorithm>
#include <sstream>

#include "engine/pipeline.h"

namespace ishibashi {
namespace {

// The anchors of a tie with its blocks turned by rotation_a and rotation_b (principal frame
// to world), m.
struct TieAnchors {
  Vec3 lever_a, lever_b;  // from each block's centroid
  Vec3 a, b;              // world
};
TieAnchors anchors(const State& s, const Tie& tie, const Mat3& rotation_a, const Mat3& rotation_b) {
  TieAnchors p;
  p.lever_a = rotation_a * tie.anchor_a_local;
  p.lever_b = rotation_b * tie.anchor_b_local;
  p.a = s.position[tie.block_a] + p.lever_a;
  p.b = s.position[tie.block_b] + p.lever_b;
  return p;
}

// The one block whose shape holds `point` (world, m) by more than `inset` (m) inside every
// face; -1 for none. `on_joint` is set to a second block that holds it within `inset` of a
// face, when the point lies on the joint between two stones.
int block_holding(const Model& m, const Vec3& point, int* on_joint) {
  int found = -1;
  *on_joint = -1;
  for (int b = 0; b < m.block_count; ++b) {
    const Vec3 local = m.initial_orientation[b].toRotationMatrix().transpose() * (point - m.initial_position[b]);
    const double inset = 1e-3 * m.size_m[b];
    double depth = INFINITY;  // of the point below the nearest face plane
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f)
      depth = std::min(depth, m.face_offset_local[f] - m.face_normal_local[f].dot(local));
    if (depth > inset && found < 0) found = b;
    else if (depth > -inset) *on_joint = b;
  }
  return found;
}

std::string point_text(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ") m";
  return s.str();
}

}  // namespace

int ModelBuilder::add_tie(const Vec3& from, const Vec3& to, double area_m2, double young_pa, double yield_pa,
                          double pretension_n) {
  Model& m = model_;
  const int t = static_cast<int>(m.ties.size());
  const std::string label = "tie " + std::to_string(t);
  if (!from.allFinite() || !to.allFinite()) throw ModelError(label + ": its anchor points must be finite");
  if (!(area_m2 > 0) || !(young_pa > 0) || !(yield_pa > 0) || !std::isfinite(area_m2 * young_pa * yield_pa))
    throw ModelError(label + ": its cross-section, Young's modulus and yield stress must be positive numbers");
  Tie tie;
  int* blocks[2] = {&tie.block_a, &tie.block_b};
  Vec3* local[2] = {&tie.anchor_a_local, &tie.anchor_b_local};
  const Vec3 points[2] = {from, to};
  for (int side = 0; side < 2; ++side) {
    int beside = -1;
    const int b = block_holding(m, points[side], &beside);
    const std::string where = label + ": its anchor at " + point_text(points[side]);
    if (b < 0 && beside >= 0)
      throw ModelError(where + " lies on a face of " + m.block_label(beside) +
                       "; anchor a tie inside one stone (a plate on a wall's outer face: a point just inside it)");
    if (b < 0) throw ModelError(where + " lies in no block; anchor a tie inside a stone");
    if (m.motion[b] != Motion::free)
      throw ModelError(where + " lies in " + m.block_label(b) + ", which does not move; a tie joins two free stones");
    *blocks[side] = b;
    *local[side] = m.initial_orientation[b].toRotationMatrix().transpose() * (points[side] - m.initial_position[b]);
  }
  if (tie.block_a == tie.block_b)
    throw ModelError(label + ": both anchors lie in " + m.block_label(tie.block_a) + "; a tie joins two stones");
  const double length = (to - from).norm();
  tie.stiffness_n_m = young_pa * area_m2 / length;
  tie.yield_force_n = yield_pa * area_m2;
  if (!(pretension_n >= 0 && pretension_n < tie.yield_force_n)) {
    std::ostringstream msg;
    msg << label << ": its pretension " << pretension_n << " N must be >= 0 and below its yield force " << tie.yield_force_n << " N";
    throw ModelError(msg.str());
  }
  tie.pretension_n = pretension_n;
  tie.rest_length_m = length - pretension_n / tie.stiffness_n_m;
  m.ties.push_back(tie);
  return t;
}

void index_ties(Model& m) {
  m.block_tie_begin.assign(m.block_count + 1, 0);
  for (const Tie& tie : m.ties) ++m.block_tie_begin[tie.block_a + 1], ++m.block_tie_begin[tie.block_b + 1];
  for (int b = 0; b < m.block_count; ++b) m.block_tie_begin[b + 1] += m.block_tie_begin[b];
  m.block_tie.resize(2 * m.ties.size());
  std::vector<int> cursor(m.block_tie_begin.begin(), m.block_tie_begin.end() - 1);
  for (std::size_t t = 0; t < m.ties.size(); ++t) {
    m.block_tie[cursor[m.ties[t].block_a]++] = static_cast<int>(2 * t);
    m.block_tie[cursor[m.ties[t].block_b]++] = static_cast<int>(2 * t + 1);
  }
}

void make_ties_snug(Model& m) {
  for (Tie& tie : m.ties) {
    const Vec3 a = m.initial_position[tie.block_a] + m.initial_orientation[tie.block_a] * tie.anchor_a_local;
    const Vec3 b = m.initial_position[tie.block_b] + m.initial_orientation[tie.block_b] * tie.anchor_b_local;
    tie.rest_length_m = (b - a).norm() - tie.pretension_n / tie.stiffness_n_m;
  }
}

double apply_ties(const Model& m, State& s) {
  double elastic_j = 0.0;
  for (std::size_t t = 0; t < m.ties.size(); ++t) {
    const Tie& tie = m.ties[t];
    const TieAnchors p = anchors(s, tie, s.rotation[tie.block_a], s.rotation[tie.block_b]);  // this step's pose
    const Vec3 span = p.b - p.a;
    const double length = span.norm();
    const double stretch = length - tie.rest_length_m - s.tie_plastic_m[t];
    double tension = stretch > 0 ? tie.stiffness_n_m * stretch : 0.0;
    if (tension > tie.yield_force_n) {  // the rod yields: it lengthens by the excess for good
      const double plastic = (tension - tie.yield_force_n) / tie.stiffness_n_m;
      s.tie_plastic_m[t] += plastic;
      s.energy.tie_yield_j += tie.yield_force_n * plastic;
      tension = tie.yield_force_n;
    }
    s.tie_tension_n[t] = tension;
    s.tie_peak_tension_n[t] = std::max(s.tie_peak_tension_n[t], tension);
    // The rod pulls b toward a and a toward b.
    const Vec3 on_b = length > 0 ? Vec3(-tension / length * span) : Vec3::Zero();
    s.tie_force_n[t] = on_b;
    s.tie_moment_nm[2 * t] = p.lever_a.cross(-on_b);
    s.tie_moment_nm[2 * t + 1] = p.lever_b.cross(on_b);
    elastic_j += 0.5 * tension * tension / tie.stiffness_n_m;
  }
  return elastic_j;
}

void add_tie_stiffness(const Model& m, const State& s, std::vector<Vec6>& stiffness) {
  for (const Tie& tie : m.ties) {
    const Mat3 rotation[2] = {s.orientation[tie.block_a].toRotationMatrix(), s.orientation[tie.block_b].toRotationMatrix()};
    const TieAnchors p = anchors(s, tie, rotation[0], rotation[1]);
    if ((p.b - p.a).norm() <= 0) continue;
    const Vec3 dir = (p.b - p.a).normalized();
    const Vec3 lever[2] = {p.lever_a, p.lever_b};
    const int block[2] = {tie.block_a, tie.block_b};
    for (int side = 0; side < 2; ++side) {
      Vec6 j;
      j << dir, rotation[side].transpose() * lever[side].cross(dir);
      // Two free blocks pulled against each other: counted twice, as block_stiffness_damping
      // counts a joint between free blocks.
      stiffness[block[side]] += 2.0 * tie.stiffness_n_m * j.cwiseAbs2();
    }
  }
}

}  // namespace ishibashi
