// The dashpot matrix's product (dashpot_product.h): the pass over the pairs.
#include "engine/dashpot_product.h"

#include <algorithm>
#include <array>

#include "engine/pair_damping.h"
#include "engine/parallel.h"

namespace ishibashi {
namespace {

// Two pairs' numbers side by side (GCC's vector extension: SSE2 lanes on x86-64).
using Two = double __attribute__((vector_size(16)));

// The dashpot resultants of a pair at its blocks' velocities xa, xb (world frame), with
// d = x_b - x_a and its matrix's entries k(i) (Sym6 order): f = -K u, the force on b and
// its moment about x_a, and on_b, the force on b and its moment about x_b. T is double
// for one pair, or Two for two pairs of the same block a, lane by lane the same
// operations in the same order (the same bits as one at a time). Written on plain
// numbers: on Eigen's 3- and 6-vectors GCC moved halves of SSE registers through the
// stack, and the loads that followed waited on the stores (a third of the pass).
template <class T, class Entry>
inline __attribute__((always_inline)) void dashpot_resultant(const T* d, const double* xa, const T* xb, Entry&& k, T* f,
                                                             T* on_b) {
  // v0 = v_b - v_a - w_b x d (the velocity of the point of b at x_a less v_a), w = w_b - w_a
  const T u[6] = {(xb[0] - xa[0]) - (xb[4] * d[2] - xb[5] * d[1]), (xb[1] - xa[1]) - (xb[5] * d[0] - xb[3] * d[2]),
                  (xb[2] - xa[2]) - (xb[3] * d[1] - xb[4] * d[0]), xb[3] - xa[3],
                  xb[4] - xa[4],                                   xb[5] - xa[5]};
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) {
    T sum = k(kSymIndex[i][0]) * u[0];
#pragma GCC unroll 5
    for (int j = 1; j < 6; ++j) sum += k(kSymIndex[i][j]) * u[j];
    f[i] = -sum;
  }
  on_b[0] = f[0], on_b[1] = f[1], on_b[2] = f[2];
  on_b[3] = f[3] - (d[1] * f[2] - d[2] * f[1]);
  on_b[4] = f[4] - (d[2] * f[0] - d[0] * f[2]);
  on_b[5] = f[5] - (d[0] * f[1] - d[1] * f[0]);
}

// Pair p at xa, xb: its force and moment on a added to on_a, those on b written to on_b.
// The pass streams the pair matrices from memory on a large model (model F: 1.4 MB), so
// nothing else is stored per pair: the lever d comes from the blocks' positions.
inline __attribute__((always_inline)) void resultant_inline(const State& s, const double* xa, const double* xb,
                                                            std::ptrdiff_t p, double* on_a, double* on_b) {
  const auto [a, b] = s.implicit.blocks[p];
  const double d[3] = {s.position[b][0] - s.position[a][0], s.position[b][1] - s.position[a][1],
                       s.position[b][2] - s.position[a][2]};
  const float* k = s.implicit.pair_matrix[p].v;
  double f[6];
  dashpot_resultant(d, xa, xb, [&](int i) { return double{k[i]}; }, f, on_b);
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) on_a[i] -= f[i];
}

}  // namespace

void pair_resultant(const State& s, const double* xa, const double* xb, std::ptrdiff_t p, double* on_a, double* on_b) {
  resultant_inline(s, xa, xb, p, on_a, on_b);
}

namespace {

// Block i's lists from its entries of State::block_pair: its pairs with dashpots where it
// is a (pair order: the entries are), then those where it is b. Written without a branch per
// entry (model F's pairs without dashpots, most of a cracked bridge's, lie scattered): an
// entry that does not belong is written and then overwritten, at worst in the spare slot.
void make_block_lists(State& s, std::ptrdiff_t i) {
  ImplicitDamping& w = s.implicit;
  int at = dashpot_lists_begin(s, i);
  for (int q = s.block_pair_begin[i]; q < s.block_pair_begin[i + 1]; ++q) {
    const int p = s.block_pair[q] >> 1;
    w.dashpot_pairs[at] = p;
    at += (~s.block_pair[q] & 1) & int{has_dashpots(w, p)};
  }
  w.a_end[i] = at;
  for (int q = s.block_pair_begin[i]; q < s.block_pair_begin[i + 1]; ++q) {
    const int p = s.block_pair[q] >> 1;
    w.dashpot_pairs[at] = p;
    at += (s.block_pair[q] & 1) & int{has_dashpots(w, p)};
  }
  w.b_end[i] = at;
}

}  // namespace

// Once a step, after the contact law. Most steps change the dashpots of a few pairs (model
// F cracked: about 14 a step, in three steps of four): only their two blocks' lists are
// marked. Every block's when the pair list changed or a chunk of the contact law noted
// more changes than it keeps.
void mark_stale_dashpot_lists(const Model& m, State& s) {
  ImplicitDamping& w = s.implicit;
  const int nb = m.block_count;
  bool all = w.lists_stale || w.relist.size() != static_cast<std::size_t>(nb);
  for (int n : w.changed_count) all |= n > ImplicitDamping::kChangedPerChunk;
  if (all) {
    w.dashpot_pairs.resize(s.block_pair.size() + nb);
    w.a_end.resize(nb);
    w.b_end.resize(nb);
    w.relist.assign(nb, 1);
    w.lists_stale = false;
  } else {
    for (std::size_t k = 0; k < w.changed_count.size(); ++k)
      for (int c = 0; c < w.changed_count[k]; ++c) {
        const Pair& pair = s.pairs[w.changed[k][c]];
        w.relist[pair.a] = w.relist[pair.b] = 1;
      }
  }
  std::fill(w.changed_count.begin(), w.changed_count.end(), 0);
}

void update_dashpot_lists(State& s, std::ptrdiff_t i) {
  std::uint8_t& stale = s.implicit.relist[i];
  if (!stale) return;
  make_block_lists(s, i);
  stale = 0;
}

bool dashpot_lists_are_current(const State& s, int nb) {
  const ImplicitDamping& w = s.implicit;
  for (int i = 0; i < nb; ++i) {
    int at = dashpot_lists_begin(s, i);
    for (int side = 0; side < 2; ++side) {
      for (int q = s.block_pair_begin[i]; q < s.block_pair_begin[i + 1]; ++q)
        if ((s.block_pair[q] & 1) == side && has_dashpots(w, s.block_pair[q] >> 1) && w.dashpot_pairs[at++] != s.block_pair[q] >> 1)
          return false;
      if (at != (side == 0 ? w.a_end[i] : w.b_end[i])) return false;
    }
  }
  return true;
}

namespace {

// The product's pass over the pairs: every pair's dashpot resultants at the velocities
// velocity_of(block, x) writes, in the block loops' chunks (a thread's pairs are those
// of its blocks). Each block's own pairs (those where it is a) are summed here into on_a,
// in pair order; only the other side is stored per pair (on_b) for the gather: what the
// pass writes and the gather reads, the two streams of a product, are a third smaller.
// A block's pairs go two at a time, one per lane.
template <class VelocityOf>
void pair_products(const Model& m, State& s, VelocityOf&& velocity_of) {
  ImplicitDamping& w = s.implicit;
  parallel_chunks(m.block_count, stage_chunks(m.block_count), [&](std::ptrdiff_t begin, std::ptrdiff_t end, int) {
    for (std::ptrdiff_t a = begin; a < end; ++a) {
      double on_a[6] = {0, 0, 0, 0, 0, 0};
      double xa[6];
      velocity_of(a, xa);
      const Vec3& position_a = s.position[a];
      int q = dashpot_lists_begin(s, a);
      const int last = w.a_end[a];
      for (; q + 1 < last; q += 2) {
        const int p0 = w.dashpot_pairs[q], p1 = w.dashpot_pairs[q + 1];
        const int b0 = w.blocks[p0][1], b1 = w.blocks[p1][1];
        double x0[6], x1[6];
        velocity_of(b0, x0);
        velocity_of(b1, x1);
        Two d[3], xb[6], f[6], on_b[6];
        for (int i = 0; i < 3; ++i)
          d[i] = Two{s.position[b0][i] - position_a[i], s.position[b1][i] - position_a[i]};
        for (int i = 0; i < 6; ++i) xb[i] = Two{x0[i], x1[i]};
        const float *k0 = w.pair_matrix[p0].v, *k1 = w.pair_matrix[p1].v;
        dashpot_resultant(d, xa, xb, [&](int i) { return Two{double{k0[i]}, double{k1[i]}}; }, f, on_b);
        for (int i = 0; i < 6; ++i) on_a[i] -= f[i][0];
        for (int i = 0; i < 6; ++i) on_a[i] -= f[i][1];
        double *out0 = w.on_b[p0].data(), *out1 = w.on_b[p1].data();
        for (int i = 0; i < 6; ++i) out0[i] = on_b[i][0], out1[i] = on_b[i][1];
      }
      if (q < last) {
        const int p = w.dashpot_pairs[q];
        double xb[6];
        velocity_of(w.blocks[p][1], xb);
        resultant_inline(s, xa, xb, p, on_a, w.on_b[p].data());
      }
      w.on_a[a] = Vec6(on_a[0], on_a[1], on_a[2], on_a[3], on_a[4], on_a[5]);
    }
  });
}

}  // namespace

void pair_products_at(const Model& m, State& s, const std::vector<Vec6>& x) {
  pair_products(m, s, [&](std::ptrdiff_t block, double* out) {
    for (int i = 0; i < 6; ++i) out[i] = x[block][i];
  });
}

// CG's direction update is done here on the fly for each pair's two blocks, and stored
// by the block pass that follows: one pass over the blocks less per iteration.
void pair_products_at_next_direction(const Model& m, State& s, double beta) {
  const ImplicitDamping& w = s.implicit;
  pair_products(m, s, [&](std::ptrdiff_t block, double* out) {
    const double *z = w.preconditioned[block].data(), *p = w.direction[block].data();
    for (int i = 0; i < 6; ++i) out[i] = z[i] + beta * p[i];
  });
}

}  // namespace ishibashi
