// Force gather: each block sums the resultants of its own pairs (summed per pair by the
// contact law), found through a block -> pair index, so no two threads write the same
// block (no atomics, and the summation order, hence the result, is the same for any
// thread count).
#include <array>
#include <cstdint>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

// The list of pair sides on prescribed blocks changed (State::prescribed_entry_next): the
// previous pose's forces of the sides listed until now are summed per block, since the
// trapezoid rule needs only each block's total of them, and the new list starts from none.
void carry_prescribed_forces(State& s) {
  for (std::size_t q = 0; q < s.prescribed_entry.size(); ++q) {
    const int block = s.prescribed_entry[q][1];
    s.prescribed_force_carried[block] += s.prescribed_entry_force_before[q];
    s.prescribed_moment_carried[block] += s.prescribed_entry_moment_before[q];
  }
  s.prescribed_entry.swap(s.prescribed_entry_next);
  s.prescribed_entry_force_before.assign(s.prescribed_entry.size(), Vec3::Zero());
  s.prescribed_entry_moment_before.assign(s.prescribed_entry.size(), Vec3::Zero());
}

// Adds to f and t a block's sides [begin, end) of `sides`: side 2 i, the block is item i's
// first (a pair's a, a tie's block_a), 2 i + 1 its second; forces[i] is item i's force on
// its second block, moments[side] its moment about the block's centroid.
inline void add_sides(const std::vector<int>& sides, int begin, int end, const std::vector<Vec3>& forces,
                      const std::vector<Vec3>& moments, Vec3& f, Vec3& t) {
  for (int q = begin; q < end; ++q) {
    const int side = sides[q];
    if (side & 1)
      f += forces[side >> 1];
    else
      f -= forces[side >> 1];
    t += moments[side];
  }
}

}  // namespace

void update_pair_index(const Model& m, State& s) {
  // Counting sort of (pair, side) entries by block; entry 2p is side a, 2p+1 side b.
  const int nb = m.block_count;
  const int np = static_cast<int>(s.pairs.size());
  s.block_pair_begin.assign(nb + 1, 0);
  for (const Pair& p : s.pairs) {
    ++s.block_pair_begin[p.a + 1];
    ++s.block_pair_begin[p.b + 1];
  }
  for (int b = 0; b < nb; ++b) s.block_pair_begin[b + 1] += s.block_pair_begin[b];
  s.block_pair.resize(2 * static_cast<std::size_t>(np));
  s.block_pair_cursor.assign(s.block_pair_begin.begin(), s.block_pair_begin.end() - 1);
  for (int p = 0; p < np; ++p) {
    s.block_pair[s.block_pair_cursor[s.pairs[p].a]++] = 2 * p;
    s.block_pair[s.block_pair_cursor[s.pairs[p].b]++] = 2 * p + 1;
  }
  // Pairs are sorted by a: chunk k of the pair loops starts at the first pair whose a is in
  // chunk k of the block loops, so a thread's range of pairs is that of its blocks.
  const int chunks = stage_chunks(nb);
  s.pair_chunk_begin.resize(chunks + 1);
  int p = 0;
  for (int k = 0; k <= chunks; ++k) {
    const int first_block = static_cast<int>(std::int64_t{nb} * k / chunks);
    while (p < np && s.pairs[p].a < first_block) ++p;
    s.pair_chunk_begin[k] = k == chunks ? np : p;
  }
  // The sides of pairs that touch a prescribed block, for the power it puts in.
  std::vector<std::array<int, 2>>& listed = s.prescribed_entry_next;
  listed.clear();
  s.prescribed_entry_begin.resize(chunks + 1);
  for (int k = 0; k < chunks; ++k) {
    s.prescribed_entry_begin[k] = static_cast<int>(listed.size());
    for (int q = s.pair_chunk_begin[k]; q < s.pair_chunk_begin[k + 1]; ++q) {
      const int a = s.pairs[q].a, b = s.pairs[q].b;
      if (m.motion[a] == Motion::prescribed) listed.push_back({2 * q, a});
      if (m.motion[b] == Motion::prescribed) listed.push_back({2 * q + 1, b});
    }
  }
  s.prescribed_entry_begin[chunks] = static_cast<int>(listed.size());
  if (listed != s.prescribed_entry) carry_prescribed_forces(s);
  s.implicit.lists_stale = true;  // the solve's lists of pairs with dashpots follow block_pair
  s.pair_index_valid = true;
}

void gather_block(const Model& m, State& s, std::ptrdiff_t b) {
  // A prescribed block moves as the driver says, whatever its forces: not gathered.
  // The ground slab, one block with hundreds of pairs, made one thread's chunk the
  // stage's slowest (imbalance 1.6-1.7 on 16 threads), its pairs' forces written by
  // every other core.
  if (m.motion[b] == Motion::prescribed) {
    s.force[b] = s.applied_force[b];
    s.torque[b] = s.applied_torque[b];
    return;
  }
  Vec3 f = Vec3::Zero(), t = Vec3::Zero();
  add_sides(s.block_pair, s.block_pair_begin[b], s.block_pair_begin[b + 1], s.pair_force_n, s.pair_moment_nm, f, t);
  if (!m.ties.empty()) add_sides(m.block_tie, m.block_tie_begin[b], m.block_tie_begin[b + 1], s.tie_force_n, s.tie_moment_nm, f, t);
  s.force[b] = f + s.applied_force[b];
  s.torque[b] = t + s.applied_torque[b];
}

double prescribed_power_of_chunk(State& s, int k) {
  // Side by side over the chunk's pairs, whose forces the same thread's contact law wrote.
  double power = 0.0;
  for (int q = s.prescribed_entry_begin[k]; q < s.prescribed_entry_begin[k + 1]; ++q) {
    const auto [entry, block] = s.prescribed_entry[q];
    const Vec3 f = (entry & 1) ? s.pair_force_n[entry >> 1] : Vec3(-s.pair_force_n[entry >> 1]);
    const Vec3& moment = s.pair_moment_nm[entry];
    power -= 0.5 * ((f + s.prescribed_entry_force_before[q]).dot(s.velocity[block]) +
                    (moment + s.prescribed_entry_moment_before[q]).dot(s.angular_velocity[block]));
    s.prescribed_entry_force_before[q] = f;
    s.prescribed_entry_moment_before[q] = moment;
  }
  return power;
}

double carried_prescribed_power(State& s) {
  double power = 0.0;
  for (int b : s.prescribed_block) {
    power -= 0.5 * (s.prescribed_force_carried[b].dot(s.velocity[b]) + s.prescribed_moment_carried[b].dot(s.angular_velocity[b]));
    s.prescribed_force_carried[b] = s.prescribed_moment_carried[b] = Vec3::Zero();
  }
  return power;
}

}  // namespace ishibashi
