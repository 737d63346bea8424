// Stones stacked on a fixed base, for the damping tests (capped and implicit dashpots):
// the stone has distinct sides (principal axes along x, y, z), the base (block 0) is as
// thick as one stone, gravity g down.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/world.h"
#include "scenes.h"

namespace ishibashi::test {

constexpr double kG = 9.81;
const Vec3 kStone(0.64, 0.48, 0.32);

inline Model stone_stack(double h, Damping damping, int stones = 1) {
  ModelBuilder b = block_on_base(kStone, stone(h), /*base_thickness=*/kStone.z());
  for (int i = 1; i < stones; ++i) {
    const Polyhedron p = make_box(Vec3(0, 0, (i + 0.5) * kStone.z()), kStone);
    b.add_block(p.vertices, p.faces, 0, Motion::free, "stone " + std::to_string(i));
  }
  b.set_gravity(Vec3(0, 0, -kG));
  return b.build({.damping = damping});
}

// Steps w for 0.3 s and checks that its stack of `stones` settles under its weight: no
// blow-up, nothing moves any more, the base carries the stones' weight, and the energy
// balance closes within 1 % of what the dashpots dissipated.
inline void expect_stack_settles(World& w, int stones) {
  const State& s = w.state();
  const double weight = stones * stone().density_kg_m3 * kStone.prod() * kG;
  double largest_speed = 0;
  while (s.time_s < 0.3) {
    w.step();
    for (const Vec3& v : s.velocity) largest_speed = std::max(largest_speed, v.norm());
  }
  EXPECT_LT(largest_speed, 1e-2);  // m/s: a settling, not a blow-up
  for (const Vec3& v : s.velocity) EXPECT_LT(v.norm(), 1e-6);
  EXPECT_NEAR(-s.force[0].z(), weight, 1e-6 * weight);
  EXPECT_GT(s.energy.damping_j, 0.0);
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 0.01 * s.energy.damping_j);
}

}  // namespace ishibashi::test
