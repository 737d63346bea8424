// The fill of a filled bridge (BridgeSpec::fill_height_m > 0): courses of stones in running
// bond beside the rings and columns of cut stones over the shallow chords near the crowns,
// each course cut around the rings' outlines and split across the width into the two
// spandrel walls' stones (the face courses) and fill or soil units between them.
#pragma once
#include <vector>

#include "geometry/arch_ring.h"
#include "geometry/bridge.h"

namespace ishibashi {

// Appends the fill's blocks to `blocks` (side cells course by course, then the columns),
// for the spans centred at `centres` (x, m).
void add_fill(const BridgeSpec& s, const RingGeometry& g, const std::vector<double>& centres, std::vector<BridgeBlock>& blocks);

}  // namespace ishibashi
