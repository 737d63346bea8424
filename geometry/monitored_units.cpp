// The units an analysis monitors, found from the generator's part tags: the unit on top
// of the crown (the study's) and one beside it off the bridge's symmetry planes.
#include <algorithm>
#include <cmath>

#include "geometry/bridge.h"

namespace ishibashi {

int crown_unit(const Model& m) {
  int best = -1;
  auto height = [&](int b) { return m.initial_position[b].z() - 1e-3 * std::abs(m.initial_position[b].y()); };
  // Mirror units at the same height (a ring of an even number of voussoirs, the crowns of
  // equal spans) go by position, not by number: the smaller x (the first span), then y.
  auto before = [&](int b, int other) {
    if (std::abs(height(b) - height(other)) > 1e-9) return height(b) > height(other);
    const Vec3 &p = m.initial_position[b], &q = m.initial_position[other];
    return p.x() < q.x() - 1e-9 || (p.x() < q.x() + 1e-9 && p.y() < q.y() - 1e-9);
  };
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free && m.block_tag[b].part == static_cast<int>(Part::ring) && (best < 0 || before(b, best)))
      best = b;
  return best;
}

int face_unit_beside_crown(const Model& m) {
  const int crown = crown_unit(m);
  if (crown < 0) return -1;
  const Vec3 c = m.initial_position[crown];
  double face_y = -1e300;
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free && m.block_tag[b].part == static_cast<int>(Part::ring))
      face_y = std::max(face_y, m.initial_position[b].y());
  int best = -1;
  auto distance = [&](int b) { return (m.initial_position[b] - c).norm(); };
  for (int b = 0; b < m.block_count; ++b) {
    const Vec3& p = m.initial_position[b];
    if (m.motion[b] != Motion::free || m.block_tag[b].part != static_cast<int>(Part::ring) || p.y() < face_y - 1e-3 ||
        std::abs(p.x() - c.x()) < 1e-3)
      continue;
    if (best < 0 || distance(b) < distance(best) - 1e-9 || (distance(b) < distance(best) + 1e-9 && p.x() > m.initial_position[best].x()))
      best = b;
  }
  return best;
}

}  // namespace ishibashi
