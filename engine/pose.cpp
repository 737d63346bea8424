#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {

void update_pose(const Model& m, State& s) {
  parallel_for(m.block_count, [&](std::ptrdiff_t b) {
    const Mat3 r = s.rotation[b] = s.orientation[b].toRotationMatrix();
    const Vec3& x = s.position[b];
    for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) {
      s.face_normal_world[f] = r * m.face_normal_local[f];
      s.face_offset_world[f] = m.face_offset_local[f] + s.face_normal_world[f].dot(x);
    }
  });
}

}  // namespace ishibashi
