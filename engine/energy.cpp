#include "engine/pipeline.h"

namespace ishibashi {

double kinetic_energy(const Model& m, const State& s) {
  double e = 0.0;
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::free) continue;
    const Vec3 w = s.rotation[b].transpose() * s.angular_velocity[b];
    e += 0.5 * m.mass_kg[b] * s.velocity[b].squaredNorm() + 0.5 * w.dot(m.inertia_kg_m2[b].cwiseProduct(w));
  }
  return e;
}

double gravitational_energy(const Model& m, const State& s) {
  double e = 0.0;
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free) e -= m.mass_kg[b] * m.gravity_m_s2.dot(s.position[b]);
  return e;
}

}  // namespace ishibashi
