#include "analysis/run/member_draw.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>

#include "engine/pipeline.h"

namespace ishibashi {

MemberDraw draw_member(const EnsembleSpec& spec, int member) {
  DrawStream draws(spec.seed, member, kMemberDraws);
  MemberDraw d;
  d.member = member;
  d.amplitude = draws.between(spec.amplitude[0], spec.amplitude[1]);
  const double friction = draws.between(spec.friction_angle_deg[0], spec.friction_angle_deg[1]);
  d.friction_angle_deg = spec.varies_friction() ? friction : 0.0;
  return d;
}

namespace {

// Where a stone stands, as a key for its own stream of draws: the bits of its centroid
// (computed from its own vertices, so the same whatever the block's number).
std::uint64_t place_key(const Vec3& centroid) {
  std::uint64_t key = 0;
  for (int i = 0; i < 3; ++i) {
    const double x = centroid[i] + 0.0;  // -0 and +0 alike
    key = splitmix_mixed(key ^ std::bit_cast<std::uint64_t>(x));
  }
  return key;
}

void place_stones(Model& m, const EnsembleSpec& spec, const MemberDraw& draw) {
  if (draw.friction_angle_deg > 0)
    for (PairLaw& law : m.pair_law) law.tan_friction = std::tan(draw.friction_angle_deg * M_PI / 180.0);
  const double t = spec.position_tolerance_m;
  if (t == 0) return;  // the scenario's own blocks and poses, bit for bit
  struct Placement {
    Vec3 shift = Vec3::Zero(), axis = Vec3::UnitZ();
    double angle = 0;  // rad
  };
  std::vector<Placement> placement(m.block_count);
  std::vector<int> moved;  // the free blocks
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::free) continue;
    // Seven draws a stone from its own stream: (seed, member, where it stands).
    DrawStream draws(spec.seed, draw.member, kPoseDraws ^ place_key(m.initial_position[b]));
    const double cut = t * draws.uniform();
    Placement& p = placement[b];
    p.shift = Vec3(draws.between(-0.5, 0.5), draws.between(-0.5, 0.5), draws.between(-0.5, 0.5)) * t;
    const double z = draws.between(-1, 1), phi = 2 * M_PI * draws.uniform(), fraction = draws.uniform();
    moved.push_back(b);
    // Cut smaller: scaled about its centroid so that its nearest face moves in by `cut`. Its
    // mass, inertia and size stay as drawn (the cut is a fit, not less stone).
    double nearest = INFINITY;
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) nearest = std::min(nearest, m.face_offset_local[f]);
    const double scale = 1 - cut / nearest;
    for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) m.vertex_local[v] *= scale;
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) m.face_offset_local[f] *= scale;
    m.radius_m[b] *= scale;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    p.axis = Vec3(r * std::cos(phi), r * std::sin(phi), z);  // uniform on the sphere
    p.angle = fraction * 0.5 * t / m.radius_m[b];                // no point moves more than t / 2
  }
  if (moved.empty()) return;
  // Placed as drawn where that overlaps no neighbour more than the model itself does: a
  // block in a joint that overlaps has its shift and turn halved, round by round, and
  // dropped after kHalvings rounds (the cut alone only opens joints). The joints then close
  // under gravity while the bridge settles.
  constexpr int kHalvings = 8;
  constexpr double kFit = 1e-7;  // m: an overlap below this is a fit (the presets' joints touch to 1e-12 m)
  auto contacts_of = [&](const Model& model) {
    State s = make_initial_state(model);
    update_pose(model, s);
    update_pairs(model, s);
    update_contacts(model, s, /*first_detection=*/true, 1e-5);
    return std::move(s.contacts);
  };
  std::map<std::pair<int, int>, double> own;  // each pair's deepest overlap, cut but not moved (m, <= 0)
  {
    const SubContacts c = contacts_of(m);
    for (std::size_t i = 0; i < c.size(); ++i) {
      double& gap = own.try_emplace({c.block_a[i], c.block_b[i]}, 0.0).first->second;
      gap = std::min(gap, c.gap_m[i]);
    }
  }
  const std::vector<Vec3> position = m.initial_position;
  const std::vector<Quat> orientation = m.initial_orientation;
  std::vector<double> share(m.block_count, 1.0);
  for (int round = 0;; ++round) {
    for (int b : moved) {
      const Placement& p = placement[b];
      m.initial_position[b] = position[b] + share[b] * p.shift;
      m.initial_orientation[b] = share[b] > 0 ? (Quat(Eigen::AngleAxisd(share[b] * p.angle, p.axis)) * orientation[b]).normalized()
                                              : orientation[b];
    }
    const SubContacts c = contacts_of(m);
    std::vector<std::uint8_t> overlaps(m.block_count, 0);
    bool any = false;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const auto given = own.find({c.block_a[i], c.block_b[i]});
      if (c.gap_m[i] < (given == own.end() ? 0.0 : given->second) - kFit)
        overlaps[c.block_a[i]] = overlaps[c.block_b[i]] = 1, any = true;
    }
    bool changed = false;
    for (int b : moved)
      if (overlaps[b] && share[b] > 0) share[b] = round < kHalvings ? 0.5 * share[b] : 0.0, changed = true;
    if (!any || !changed) return;  // none left, or only between blocks where the cut left them
  }
}

}  // namespace

void perturb_model(Model& m, const EnsembleSpec& spec, const MemberDraw& draw) {
  place_stones(m, spec, draw);
  make_ties_snug(m);  // a rod is tightened on the bridge as it was built, each member's
}

}  // namespace ishibashi
