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
  Bond bond = Bond::stack;     // courses across the width: stacked or staggered by half a stone
  Material stone;              // empty name: the Nishida stone
};

struct Voussoir {
  Polyhedron shape;
  int ring_index;    // position along the arc, 0 at the x < 0 springing
  int course;        // position across the width
  bool fixed;        // the springing stones
};

// Throws ModelError for impossible parameters (rise above half the span, non-positive
// sizes, stones larger than the ring), naming the parameter and the allowed range.
std::vector<Voussoir> make_arch_ring(const ArchRingSpec& spec);

// The ring as an engine Model (springing stones fixed).
Model make_arch_ring_model(const ArchRingSpec& spec);

}  // namespace ishibashi
