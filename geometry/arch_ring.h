// Arch rings of voussoirs (MODEL.md section 5, Nishida model A), generated from a few
// parameters. The first slice of the bridge generator: the ring alone, on fixed springers.
#pragma once
#include <string>
#include <vector>

#include "engine/model.h"
#include "geometry/shapes.h"

namespace ishibashi {

enum class Bond { stack, running };

struct ArchRingSpec {
  double span_m = 11.36;       // clear span at the intrados springings
  double rise_m = 4.76;        // intrados rise; rise = span / 2 is semicircular
  double thickness_m = 0.64;   // ring thickness (radial)
  double width_m = 3.2;        // across the bridge (y)
  double stone_m = 0.64;       // target stone length along the arc and across the width
  int voussoirs = 0;           // voussoirs along the arc; 0: from stone_m at mid-thickness
  Bond bond = Bond::stack;     // courses across the width: stacked or staggered by half a stone
  Material stone;              // empty name: the Nishida stone
};

struct Voussoir {
  Polyhedron shape;
  int ring_index;    // position along the arc, 0 at the x < 0 springing
  int course;        // position across the width
  bool fixed;        // the springing stones
};

// The ring's circle and joints. Throws ModelError for impossible parameters (rise above
// half the span, non-positive sizes, stones larger than the ring), naming the parameter
// and the allowed range.
struct RingGeometry {
  double radius;        // intrados, m
  double outer_radius;  // extrados, m
  double centre_z;      // height of the circle's centre (springings at z = 0), m
  double half_angle;    // from the crown to a springing, rad
  int along;            // voussoirs along the arc
  int across;           // courses across the width
  double springer_half_width;  // half the ring's extent along x at the ground, m

  // Angle of radial joint j (0 .. along) from the crown, rad. Joints j and along - j get
  // exactly opposite angles, so both halves of the ring are mirror images to the bit.
  double joint(int j) const { return (2 * j - along) * (half_angle / along); }
};
RingGeometry ring_geometry(const ArchRingSpec& spec);

// The voussoirs of a ring centred at x = centre_x. With square_springers, the two
// springing stones get a vertical outer face and a flat top at the next joint's height,
// so walls and fill can stand beside them.
std::vector<Voussoir> make_arch_ring_at(const ArchRingSpec& spec, double centre_x, bool square_springers);
inline std::vector<Voussoir> make_arch_ring(const ArchRingSpec& spec) { return make_arch_ring_at(spec, 0.0, false); }

}  // namespace ishibashi
