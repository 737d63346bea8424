#include "geometry/block_order.h"

#include <algorithm>

namespace ishibashi {
namespace {

Vec3 vertex_mean(const Polyhedron& p) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& v : p.vertices) sum += v;
  return sum / static_cast<double>(p.vertices.size());
}

// Bisection stops at pieces of at most this many blocks, which keep the generator's order
// (part by part): numbered by bisection down to single blocks, the pairs' kinds (ring-ring,
// ring-fill, fill-fill, with their open, sliding and bonded branches) interleave instead
// of coming in runs, and model F's contact law took longer on one thread (perf/results).
// Pieces of 64 cross ranges nearly as little (24 % of F's pairs on 16 threads, 22 %).
constexpr std::ptrdiff_t kPieceBlocks = 64;

// Orders ids[begin, end) in place: split at the median across the longest extent of their
// points, each half ordered the same way, down to pieces of kPieceBlocks.
void bisect(std::vector<int>& ids, std::ptrdiff_t begin, std::ptrdiff_t end, const std::vector<Vec3>& point) {
  if (end - begin <= kPieceBlocks) {
    std::sort(ids.begin() + begin, ids.begin() + end);
    return;
  }
  Vec3 lo = point[ids[begin]], hi = lo;
  for (std::ptrdiff_t i = begin + 1; i < end; ++i) {
    lo = lo.cwiseMin(point[ids[i]]);
    hi = hi.cwiseMax(point[ids[i]]);
  }
  int axis;
  (hi - lo).maxCoeff(&axis);
  std::sort(ids.begin() + begin, ids.begin() + end,
            [&](int a, int b) { return point[a][axis] < point[b][axis] || (point[a][axis] == point[b][axis] && a < b); });
  const std::ptrdiff_t middle = begin + (end - begin) / 2;
  bisect(ids, begin, middle, point);
  bisect(ids, middle, end, point);
}

}  // namespace

void order_blocks_for_locality(std::vector<BridgeBlock>& blocks) {
  std::vector<Vec3> point;
  std::vector<int> free, fixed;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    point.push_back(vertex_mean(blocks[i].shape));
    (blocks[i].fixed ? fixed : free).push_back(static_cast<int>(i));
  }
  bisect(free, 0, static_cast<std::ptrdiff_t>(free.size()), point);
  std::vector<BridgeBlock> ordered;
  ordered.reserve(blocks.size());
  for (const std::vector<int>* ids : {&free, &fixed})
    for (int i : *ids) ordered.push_back(std::move(blocks[i]));
  blocks = std::move(ordered);
}

}  // namespace ishibashi
