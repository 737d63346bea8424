#include "geometry/demo_scenes.h"

#include "geometry/shapes.h"

namespace ishibashi {


Model make_wall_model(const WallSpec& w) {
  ModelBuilder builder;
  const int stone = builder.add_material(w.stone.name.empty() ? nishida_stone() : w.stone);
  const double s = w.stone_m;
  const double length = w.stones_per_course * s, depth = w.leaves * s;
  const Polyhedron base =
      make_box(Vec3(0.5 * length, 0.5 * depth, -0.5 * w.base_thickness_m), Vec3(length + 2 * s, depth + 2 * s, w.base_thickness_m));
  builder.add_block(base.vertices, base.faces, stone, w.base_motion, "base");
  for (int course = 0; course < w.courses; ++course) {
    // Running bond: odd courses are offset by half a stone, with one stone fewer.
    const bool odd = course % 2 == 1;
    const int count = odd ? w.stones_per_course - 1 : w.stones_per_course;
    for (int leaf = 0; leaf < w.leaves; ++leaf)
      for (int k = 0; k < count; ++k) {
        const Vec3 c((k + 0.5 + (odd ? 0.5 : 0.0)) * s, (leaf + 0.5) * s, (course + 0.5) * s);
        const Polyhedron p = make_box(c, Vec3(s, s, s));
        std::string label = "c";  // appended, not chained with +: GCC 12 warns (-Wrestrict) on the chain
        label += std::to_string(course);
        label += "-l";
        label += std::to_string(leaf);
        label += "-s";
        label += std::to_string(k);
        builder.add_block(p.vertices, p.faces, stone, Motion::free, label);
      }
  }
  return builder.build(w.options);
}

}  // namespace ishibashi
