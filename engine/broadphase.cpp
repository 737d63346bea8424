#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

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

// One function for the rebuild's three passes (grid, candidates per chunk, merge with the
// old list): they share the cell arrays and the chunking, and read in order.
bool update_pairs(const Model& m, State& s, bool moved) {
  if (s.pairs_valid && !moved) return false;
  const int nb = m.block_count;

  // Hashed uniform grid: one bucket per occupied cell (collisions only add candidates),
  // cell edge = the largest free block's inflated diameter, so overlapping spheres lie in
  // adjacent cells. Immobile blocks larger than that (the ground, abutments) stay out of
  // the grid: sized by them, one cell would hold the whole bridge and a rebuild would
  // cost nb^2. Each of them is tested against every block instead (nb per large block).
  double max_free_radius = 0.0;
  for (int b = 0; b < nb; ++b)
    if (m.motion[b] == Motion::free) max_free_radius = std::max(max_free_radius, m.radius_m[b]);
  auto large = [&](int b) { return m.radius_m[b] > max_free_radius; };
  s.large_block.clear();
  for (int b = 0; b < nb; ++b)
    if (large(b)) s.large_block.push_back(b);
  const double cell = 2.0 * max_free_radius + m.margin_m;
  std::uint32_t buckets = 1;
  while (buckets < 2u * static_cast<std::uint32_t>(nb)) buckets <<= 1;
  const std::uint32_t mask = buckets - 1;
  auto cell_of = [&](const Vec3& x) {
    return Eigen::Matrix<std::int64_t, 3, 1>(static_cast<std::int64_t>(std::floor(x.x() / cell)),
                                            static_cast<std::int64_t>(std::floor(x.y() / cell)),
                                            static_cast<std::int64_t>(std::floor(x.z() / cell)));
  };
  s.cell_start.assign(buckets + 1, 0);
  s.cell_block.resize(nb);
  for (int b = 0; b < nb; ++b) {
    if (large(b)) continue;
    const auto c = cell_of(s.position[b]);
    ++s.cell_start[cell_hash(c.x(), c.y(), c.z(), mask) + 1];
  }
  for (std::uint32_t c = 0; c < buckets; ++c) s.cell_start[c + 1] += s.cell_start[c];
  s.cell_cursor.assign(s.cell_start.begin(), s.cell_start.end() - 1);
  for (int b = 0; b < nb; ++b) {
    if (large(b)) continue;
    const auto c = cell_of(s.position[b]);
    s.cell_block[s.cell_cursor[cell_hash(c.x(), c.y(), c.z(), mask)]++] = b;
  }

  // Candidates per block a (partners b > a), sorted; chunks in index order keep the
  // concatenated list sorted by (a, b) whatever the thread count.
  const int chunks = kBufferChunks;
  s.chunk_pairs.resize(chunks);
  s.chunk_candidates.resize(chunks);
  parallel_chunks(nb, chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    std::vector<Pair>& out = s.chunk_pairs[k];
    std::vector<int>& cand = s.chunk_candidates[k];
    out.clear();
    auto consider = [&](int a, int b) {
      if (b > a && !both_immobile(m, a, b) && spheres_overlap(m, s, a, b)) cand.push_back(b);
    };
    for (std::ptrdiff_t ai = begin; ai < end; ++ai) {
      const int a = static_cast<int>(ai);
      cand.clear();
      if (large(a)) {
        for (int b = a + 1; b < nb; ++b) consider(a, b);
      } else {
        const auto c = cell_of(s.position[a]);
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            for (int dk = -1; dk <= 1; ++dk) {
              const std::uint32_t h = cell_hash(c.x() + di, c.y() + dj, c.z() + dk, mask);
              for (int q = s.cell_start[h]; q < s.cell_start[h + 1]; ++q) consider(a, s.cell_block[q]);
            }
        for (int b : s.large_block) consider(a, b);
      }
      std::sort(cand.begin(), cand.end());
      cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
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
