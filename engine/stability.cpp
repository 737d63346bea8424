// Stability of the explicit step, block by block: the stiffness and damping that a free
// block's sub-contacts give each of its six degrees of freedom, the largest stable dt they
// allow, and (Damping::capped) the dashpot caps that keep a chosen dt stable.
#include <cmath>

#include "engine/pipeline.h"

namespace ishibashi {
namespace {

// Per free block, the diagonal stiffness (N/m, N m/rad) and damping (N s/m, N m s/rad) of
// its sub-contacts against fixed neighbours, in 3 translations and 3 rotations about the
// principal axes, with the dashpots as the materials specify them (no caps). Rotation
// matters: corner sub-contacts make rocking stiffer than bouncing. (nb) each.
void block_stiffness_damping(const Model& m, const State& s, std::vector<Vec6>& stiffness, std::vector<Vec6>& damping) {
  stiffness.assign(m.block_count, Vec6::Zero());
  damping.assign(m.block_count, Vec6::Zero());
  const SubContacts& c = s.contacts;
  for_each_sub_contact(s, [&](int i) {
    const SpringConstants k = c.constants(i);
    const Vec3& n = c.normal[i];
    const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    // Between two free blocks the stiffest mode moves them against each other: with
    // equal masses at sqrt(2) times the frequency of a block on a fixed neighbour and
    // sqrt(2) times its damping ratio. Counting such a joint twice on each side gives
    // both (a bonded joint of Nishida A's ring at 0.8 of the one-sided limit chattered
    // for ever and broke 164 bonds under self-weight).
    const bool both_free = m.motion[c.block_a[i]] == Motion::free && m.motion[c.block_b[i]] == Motion::free;
    const double weight = both_free ? 2.0 : 1.0;
    for (int b : {c.block_a[i], c.block_b[i]}) {
      if (m.motion[b] != Motion::free) continue;
      const Mat3 to_body = s.orientation[b].toRotationMatrix().transpose();
      const Vec3 r = c.point[i] - s.position[b];
      auto add = [&](const Vec3& dir, double kk, double cc) {
        Vec6 j;
        j << dir, to_body * r.cross(dir);
        stiffness[b] += weight * kk * j.cwiseAbs2();
        damping[b] += weight * cc * j.cwiseAbs2();
      };
      add(n, k.kn, k.cn);
      add(t1, k.ks, k.cs);
      add(t2, k.ks, k.cs);
    }
  });
  add_tie_stiffness(m, s, stiffness);
}

Vec6 block_mass(const Model& m, int b) {
  Vec6 mass;
  mass << Vec3::Constant(m.mass_kg[b]), m.inertia_kg_m2[b];
  return mass;
}

// Angular frequency (rad/s) and damping ratio of one mode: stiffness k, damping c, mass m.
struct Mode {
  double omega, zeta;
};
Mode mode_of(double k, double c, double m) { return {std::sqrt(k / m), c / (2.0 * std::sqrt(k * m))}; }

}  // namespace

std::vector<BlockLimit> block_stability_limits(const Model& m, const State& s, bool with_damping) {
  std::vector<Vec6> stiffness, damping;
  block_stiffness_damping(m, s, stiffness, damping);
  std::vector<BlockLimit> limits(m.block_count);
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::free) continue;
    const Vec6 mass = block_mass(m, b);
    BlockLimit& limit = limits[b];
    for (int j = 0; j < 6; ++j) {
      if (stiffness[b][j] <= 0) continue;
      // 2/omega (sqrt(1 + zeta^2) - zeta): Cundall's 2 sqrt(m / K) when undamped.
      const Mode mode = mode_of(stiffness[b][j], damping[b][j], mass[j]);
      const double zeta = with_damping ? mode.zeta : 0.0;
      const double dof_limit = 2.0 / mode.omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
      if (dof_limit < limit.dt_s) limit = {dof_limit, j};
    }
  }
  return limits;
}

double stability_limit_s(const Model& m, const State& s, bool with_damping, int* block) {
  const std::vector<BlockLimit> limits = block_stability_limits(m, s, with_damping);
  double best = INFINITY;
  for (int b = 0; b < m.block_count; ++b)
    if (limits[b].dt_s < best) {
      best = limits[b].dt_s;
      if (block) *block = b;
    }
  return best;
}

void update_damping_caps(const Model& m, State& s, double dt_s) {
  std::vector<Vec6>& stiffness = s.cap_stiffness;
  std::vector<Vec6>& damping = s.cap_damping;
  block_stiffness_damping(m, s, stiffness, damping);
  s.damping_scale.assign(m.block_count, 1.0);
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::free) continue;
    const Vec6 mass = block_mass(m, b);
    for (int j = 0; j < 6; ++j) {
      if (stiffness[b][j] <= 0 || damping[b][j] <= 0) continue;
      // dt <= kDampingCapMargin * 2/omega (sqrt(1 + zeta^2) - zeta) holds for
      // zeta <= (1 - x^2) / (2 x), x = omega dt / (2 kDampingCapMargin).
      const Mode mode = mode_of(stiffness[b][j], damping[b][j], mass[j]);
      const double x = mode.omega * dt_s / (2.0 * kDampingCapMargin);
      const double zeta_max = std::max(0.0, (1.0 - x * x) / (2.0 * x));
      if (mode.zeta > zeta_max) s.damping_scale[b] = std::min(s.damping_scale[b], zeta_max / mode.zeta);
    }
  }
}

}  // namespace ishibashi
