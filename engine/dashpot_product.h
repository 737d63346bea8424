// The dashpot matrix's product for the implicit dashpots (implicit_damping.cpp): its pass
// over the pairs and its gather. C x is the dashpot forces of every pair at velocities
// x (6 per block, world frame), pair by pair from the pair matrices the contact law sums
// (pair_damping.h), then gathered block by block in a fixed order.
#pragma once
#include <vector>

#include "engine/math.h"
#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

// Whether pair p has dashpots this step (the contact law marks one without sub-contacts).
inline bool has_dashpots(const ImplicitDamping& w, std::ptrdiff_t p) { return w.blocks[p][1] >= 0; }

// Each block's lists of its pairs with dashpots (ImplicitDamping::dashpot_pairs) let the
// passes loop over them without a test per pair. Once a step, after the contact law: marks
// the blocks whose lists are out of date (ImplicitDamping::relist). Then, before any pass
// reads them, update_dashpot_lists(s, i) makes block i's anew if marked: the solve's first
// pass over the blocks calls it for each (a block's lists need no other block's, so the
// team shares the work, which one thread did between the passes: model F, about 30 us a step).
void mark_stale_dashpot_lists(const Model& m, State& s);
void update_dashpot_lists(State& s, std::ptrdiff_t i);

// Whether every block's lists are those read off the pairs now (debug builds' check).
bool dashpot_lists_are_current(const State& s, int nb);

// Where block i's lists begin in ImplicitDamping::dashpot_pairs: its range of
// State::block_pair's length, and one spare slot per block before it.
inline int dashpot_lists_begin(const State& s, std::ptrdiff_t i) { return s.block_pair_begin[i] + static_cast<int>(i); }

// The product's pass over the pairs at x (x zero where not solved), into
// ImplicitDamping::on_a and on_b.
void pair_products_at(const Model& m, State& s, const std::vector<Vec6>& x);

// The same at conjugate gradients' next search direction z + beta p, formed on the fly
// from ImplicitDamping::preconditioned and direction for each pair's two blocks.
void pair_products_at_next_direction(const Model& m, State& s, double beta);

// Pair p's dashpot resultants at its blocks' velocities xa, xb: the force and moment on
// a about x_a added to on_a, those on b about x_b written to on_b (N, N m).
void pair_resultant(const State& s, const double* xa, const double* xb, std::ptrdiff_t p, double* on_a, double* on_b);

// The gathered dashpot force and moment on block b from the last product's pair pass
// (N, N m): its own pairs' sum, then the pairs where it is b, in the gather's order.
// The sums are plain doubles, kept in registers (a Vec6 was stored back at every entry).
inline Vec6 gathered(const State& s, std::ptrdiff_t b) {
  const ImplicitDamping& w = s.implicit;
  const double* own = w.on_a[b].data();
  double f[6] = {own[0], own[1], own[2], own[3], own[4], own[5]};
  for (int q = w.a_end[b]; q < w.b_end[b]; ++q) {
    const double* r = w.on_b[w.dashpot_pairs[q]].data();
    for (int i = 0; i < 6; ++i) f[i] += r[i];
  }
  return Vec6(f[0], f[1], f[2], f[3], f[4], f[5]);
}

}  // namespace ishibashi
