// The order in which a generated bridge numbers its blocks. The step's loops give each
// thread one contiguous range of blocks, and of pairs by their first block, the same range
// from step to step (engine/team.h); a pair whose blocks lie in two threads' ranges moves
// their data between the cores' caches every step. Numbered part by part (rings, then the
// fill, then the walls), model F's neighbours were a median 110 numbers apart, and on 16
// threads 59 % of its pairs crossed two ranges (15 % on 2); numbered so that every range
// is a compact piece of the bridge, 24 % (4 % on 2).
#pragma once
#include <vector>

#include "geometry/bridge.h"

namespace ishibashi {

// Reorders the free blocks by recursive coordinate bisection of their vertices' means
// (each set split at its median across its longest extent, the lower half first), then
// the fixed blocks in their given order (the ground slab, which the generator adds
// last, stays last). Deterministic: ties go by the given order.
void order_blocks_for_locality(std::vector<BridgeBlock>& blocks);

}  // namespace ishibashi
