// Small ready-made scenes: a masonry wall in running bond on a base slab. Used by the
// demo command, the determinism test and the benchmarks.
#pragma once
#include "engine/model.h"
#include "geometry/materials.h"

namespace ishibashi {

struct WallSpec {
  int courses = 6;              // rows of stones
  int stones_per_course = 5;    // stones in the longer courses (running bond alternates n, n-1)
  int leaves = 1;               // wythes across the thickness
  double stone_m = 0.64;        // cubic stone edge
  double base_thickness_m = 0.5;
  Motion base_motion = Motion::prescribed;  // the base the driver shakes or tilts
  Material stone;               // defaults to the Nishida stone (MODEL.md section 4)
  ModelOptions options;         // subdivision, capped dashpots
};

// Block 0 is the base; the stones follow course by course from the bottom.
Model make_wall_model(const WallSpec& spec);

}  // namespace ishibashi
