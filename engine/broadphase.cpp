#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

bool both_immobile(const Model& m, int a, int b) {
  return m.motion[a] != Motion::free && m.motion[b] != Motion::free;
}

std::uint32_t cell_hash(std::int64_t i, std::int64_t j, std::int64_t k, std::uint32_t mask) {
  const std::uint64_t h = static_cast<std::uint64_t>(i) * 73856093u ^ static_cast<std::uint64_t>(j) * 19349663u ^
                          static_cast<std::uint64_t>(k) * 83492791u;
  return static_cast<std::uint32_t>(h) & mask;
}

}  // namespace

// Bounding spheres about the centroids, inflated by half the margin each. Being
// rotation-invariant, they stay valid until a block has translated by half the margin;
// tighter than their cubes, they leave out the diagonal neighbours of masonry courses.
bool spheres_overlap(const Model& m, const State& s, int a, int b) {
  const double reach = m.radius_m[a] + m.radius_m[b] + m.margin_m;
  return (s.position[a] - s.position[b]).squaredNorm() < reach * reach;
}

std::vector<Pair> brute_force_pairs(const Model& m, const State& s) {
  std::vector<Pair> out;
  for (int a = 0; a < m.block_count; ++a)
    for (int b = a + 1; b < m.block_count; ++b)
      if (!both_immobile(m, a, b) && spheres_overlap(m, s, a, b)) out.push_back(Pair{a, b});
  return out;
}

bool update_pairs(const Model& m, State& s) {
  bool moved = !s.pairs_valid;
  for (int b = 0; b < m.block_count && !moved; ++b) moved = moved_half_margin(m, s, b);
  return update_pairs(m, s, moved);
}

// The hashed uniform grid of the broadphase: one bucket per occupied cell (collisions only
// add candidates), cell edge = the largest free block's inflated diameter, so overlapping
// spheres lie in adjacent cells. Immobile blocks larger than that (the ground, abutments)
// stay out of the grid: sized by them, one cell would hold the whole bridge and a rebuild
// would cost nb^2. Each of them is tested against every block instead (nb per large block).
// Fills s.cell_start, s.cell_block and s.large_block.
class CellGrid {
 public:
  CellGrid(const Model& m, State& s) : m_(m), s_(s) {
    const int nb = m.block_count;
    for (int b = 0; b < nb; ++b)
      if (m.motion[b] == Motion::free) max_free_radius_ = std::max(max_free_radius_, m.radius_m[b]);
    s.large_block.clear();
    for (int b = 0; b < nb; ++b)
      if (large(b)) s.large_block.push_back(b);
    cell_ = 2.0 * max_free_radius_ + m.margin_m;
    std::uint32_t buckets = 1;
    while (buckets < 2u * static_cast<std::uint32_t>(nb)) buckets <<= 1;
    mask_ = buckets - 1;
    s.cell_start.assign(buckets + 1, 0);
    s.cell_block.resize(nb);
    for (int b = 0; b < nb; ++b) {
      if (large(b)) continue;
      const auto c = cell_of(s.position[b]);
      ++s.cell_start[cell_hash(c.x(), c.y(), c.z(), mask_) + 1];
    }
    for (std::uint32_t c = 0; c < buckets; ++c) s.cell_start[c + 1] += s.cell_start[c];
    s.cell_cursor.assign(s.cell_start.begin(), s.cell_start.end() - 1);
    for (int b = 0; b < nb; ++b) {
      if (large(b)) continue;
      const auto c = cell_of(s.position[b]);
      s.cell_block[s.cell_cursor[cell_hash(c.x(), c.y(), c.z(), mask_)]++] = b;
    }
  }

  // Block a's partners b > a whose inflated spheres overlap its own, sorted, into `cand`.
  void candidates(int a, std::vector<int>& cand) const {
    cand.clear();
    auto consider = [&](int b) {
      if (b > a && !both_immobile(m_, a, b) && spheres_overlap(m_, s_, a, b)) cand.push_back(b);
    };
    if (large(a)) {
      for (int b = a + 1; b < m_.block_count; ++b) consider(b);
    } else {
      const auto c = cell_of(s_.position[a]);
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk) {
            const std::uint32_t h = cell_hash(c.x() + di, c.y() + dj, c.z() + dk, mask_);
            for (int q = s_.cell_start[h]; q < s_.cell_start[h + 1]; ++q) consider(s_.cell_block[q]);
          }
      for (int b : s_.large_block) consider(b);
    }
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  }

 private:
  bool large(int b) const { return m_.radius_m[b] > max_free_radius_; }
  // Clamped so that a stone thrown absurdly far (a hand-made checkpoint's 1e293 m) still has
  // a cell: a cell shared far out only adds candidates, which the spheres' test then drops.
  Eigen::Matrix<std::int64_t, 3, 1> cell_of(const Vec3& x) const {
    auto index = [this](double coordinate) {
      constexpr double kFarthest = 1e15;  // cells each way; the hash's neighbours stay within int64
      return static_cast<std::int64_t>(std::clamp(std::floor(coordinate / cell_), -kFarthest, kFarthest));
    };
    return {index(x.x()), index(x.y()), index(x.z())};
  }

  const Model& m_;
  const State& s_;
  double max_free_radius_ = 0.0, cell_ = 0.0;
  std::uint32_t mask_ = 0;
};

void refuse_crowded_spheres(const Model& m, State& s) {
  const long long limit = max_candidate_pairs(m.block_count);
  const CellGrid grid(m, s);
  std::vector<int> cand, partners(m.block_count, 0);
  long long pairs = 0;
  for (int a = 0; a < m.block_count && pairs <= limit; ++a) {
    grid.candidates(a, cand);
    pairs += static_cast<long long>(cand.size());
    partners[a] += static_cast<int>(cand.size());
    for (int b : cand) ++partners[b];
  }
  if (pairs <= limit) return;
  const int busiest = static_cast<int>(std::max_element(partners.begin(), partners.end()) - partners.begin());
  std::ostringstream msg;
  msg.precision(3);
  msg << "the blocks' bounding spheres overlap in more than " << limit << " pairs (" << kMaxPairsPerBlock
      << " a block; a masonry assembly has about 10): that of " << m.block_label(busiest) << ", " << 2 * m.radius_m[busiest]
      << " m across, meets those of " << partners[busiest] << " others. Blocks far thinner than they are long, side by "
      << "side, would exhaust the memory: make them closer to cubes (a bridge's stone_m, in metres, is its ring stones' "
      << "width)";
  throw ModelError(msg.str());
}

// One function for the rebuild's three passes (grid, candidates per chunk, merge with the
// old list): they share the cell arrays and the chunking, and read in order.
bool update_pairs(const Model& m, State& s, bool moved) {
  if (s.pairs_valid && !moved) return false;
  const CellGrid grid(m, s);

  // Candidates per block a (partners b > a), sorted; chunks in index order keep the
  // concatenated list sorted by (a, b) whatever the thread count.
  const int chunks = kBufferChunks;
  s.chunk_pairs.resize(chunks);
  s.chunk_candidates.resize(chunks);
  parallel_chunks(m.block_count, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    std::vector<Pair>& out = s.chunk_pairs[k];
    std::vector<int>& cand = s.chunk_candidates[k];
    out.clear();
    for (std::ptrdiff_t ai = begin; ai < end; ++ai) {
      const int a = static_cast<int>(ai);
      grid.candidates(a, cand);
      for (int b : cand) out.push_back(Pair{a, b});
    }
  });

  // Merge with the old list: a pair that survives keeps its axis and contact range.
  s.pair_scratch.clear();
  std::size_t old = 0;
  for (const auto& chunk : s.chunk_pairs)
    for (Pair p : chunk) {
      while (old < s.pairs.size() &&
             (s.pairs[old].a < p.a || (s.pairs[old].a == p.a && s.pairs[old].b < p.b)))
        ++old;
      if (old < s.pairs.size() && s.pairs[old].a == p.a && s.pairs[old].b == p.b) p = s.pairs[old];
      s.pair_scratch.push_back(p);
    }
  std::swap(s.pairs, s.pair_scratch);
  s.position_at_rebuild = s.position;
  s.pairs_valid = true;
  s.pairs_changed = true;
  s.pair_index_valid = false;
  return true;
}

}  // namespace ishibashi
