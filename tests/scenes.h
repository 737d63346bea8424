// Small scenes for the physics tests: blocks on a fixed base, with materials whose
// closed-form answers the tests compute independently of the engine.
#pragma once
#include <utility>
#include <vector>

#include "engine/model.h"
#include "engine/pipeline.h"
#include "engine/state.h"
#include "geometry/shapes.h"

namespace ishibashi::test {

inline Material stone(double damping = 1.0, double friction_deg = 33.23, double bond_pa = 0.0) {
  Material m;
  m.name = "stone";
  m.density_kg_m3 = 1.88e3;
  m.young_pa = 1.4039e10;
  m.poisson = 0.28;
  m.friction_deg = friction_deg;
  m.tensile_pa = bond_pa;
  m.cohesion_pa = bond_pa;
  m.damping_normal = damping;
  m.damping_shear = damping;
  return m;
}

// A fixed base slab (top face at z = 0, thickness `base_thickness`, wide) and one box
// block of size `size` standing on it, centred at x = y = 0. Block 0 is the base.
inline ModelBuilder block_on_base(const Vec3& size, const Material& material, double base_thickness = 0.64,
                                  double base_width = 4.0) {
  ModelBuilder b;
  const int mat = b.add_material(material);
  const Polyhedron base = make_box(Vec3(0, 0, -0.5 * base_thickness), Vec3(base_width, base_width, base_thickness));
  b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
  const Polyhedron block = make_box(Vec3(0, 0, 0.5 * size.z()), size);
  b.add_block(block.vertices, block.faces, mat, Motion::free, "block");
  return b;
}

// Blocks of the stone material in the given order (block i is blocks[i]), each fixed or free.
inline Model stones_model(const std::vector<std::pair<const Polyhedron*, Motion>>& blocks, const ModelOptions& options = {}) {
  ModelBuilder b;
  const int mat = b.add_material(stone());
  for (const auto& [shape, motion] : blocks) b.add_block(shape->vertices, shape->faces, mat, motion);
  return b.build(options);
}

// The sub-contacts the narrowphase finds for a model in its initial pose (a first search).
inline State contacts_found(const Model& m) {
  State s = make_initial_state(m);
  update_pose(m, s);
  update_pairs(m, s);
  update_contacts(m, s, true, 1e-5);
  return s;
}

// Normal spring of a face-face joint of area S between two blocks of the same material,
// centroids at l_a and l_b from the joint (MODEL.md section 3).
inline double joint_normal_stiffness(double area, double l_a, double l_b, double young) {
  return area / (l_a / young + l_b / young);
}

}  // namespace ishibashi::test
