// Implicit dashpots (Damping::implicit, issue 28): the contact law applies the springs
// only; this stage finds the velocities at the end of the step with every dashpot
// evaluated there, backward Euler in the damping,
//   (M + dt C) v_new = M v* + (dt C_p v_p),
// with v* the velocities semi-implicit Euler gives without the dashpots, C the dashpot
// matrix of the free blocks' sub-contacts and v_p the prescribed blocks' velocities. Its
// unknown is the change the dashpots make, delta = v_new - v* (6 per free block), found
// by conjugate gradients preconditioned with each block's own 6x6 diagonal block of
// M + dt C, matrix-free: a product is one pass over the pairs' 6x6 dashpot matrices
// (pair_damping.h, summed by the contact law as it leaves each sub-contact) and a gather.
// Backward Euler never amplifies a damped mode, so dt is limited by the springs alone
// (explicit dashpots with h = 1 on a block held by many joints: a tenth of that or less).
// The change is handed to integrate_with_dashpots() as the force M delta / dt.
// Every sum runs in fixed chunks in a fixed order: the result is the same for any team.
#include <array>
#include <cassert>
#include <cmath>

#include "engine/dashpot_product.h"
#include "engine/pair_damping.h"
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

Vec3 linear(const Vec6& v) { return v.head<3>(); }
Vec3 angular(const Vec6& v) { return v.tail<3>(); }

// (linear, angular) as one 6-vector. Not Eigen's comma initializer: its blocks have sizes
// known only at run time, and that generic loop was 1.2 % of a cracked bridge's step.
Vec6 stacked(const Vec3& translation, const Vec3& rotation) {
  Vec6 v;
  v.head<3>() = translation;
  v.tail<3>() = rotation;
  return v;
}

bool solved(const Model& m, const State& s, std::ptrdiff_t b) { return m.motion[b] == Motion::free && !s.left_model[b]; }

// Block b's mass matrix applied to x (world frame): m x_v and R I R^T x_w.
Vec6 mass_times(const Model& m, const State& s, std::ptrdiff_t b, const Vec6& x) {
  const Mat3& r = s.rotation[b];
  return stacked(m.mass_kg[b] * linear(x), r * m.inertia_kg_m2[b].cwiseProduct(r.transpose() * angular(x)));
}

// A pair matrix's three 3x3 blocks, K = [[k11, k12], [k12^T, k22]].
struct PairBlocks {
  Mat3 k11, k12, k22;
};
PairBlocks blocks_of(const Sym6f& k) {
  PairBlocks out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      out.k11(i, j) = k.v[kSymIndex[i][j]];
      out.k12(i, j) = k.v[kSymIndex[i][3 + j]];
      out.k22(i, j) = k.v[kSymIndex[3 + i][3 + j]];
    }
  return out;
}

// Block b's diagonal block of M + dt C, inverted. Its pairs' matrices: as they are where b
// is a (its velocity enters v0 and w with a minus sign), and S^T K S where b is b, with
// S = [[I, [d]x], [0, I]] mapping (v_b, w_b) to (v0, w), d = x_b - x_a. Summed as 3x3
// blocks (Eigen's corner views of a 6x6 ran through its generic loops).
Mat6 diagonal_inverse(const Model& m, const State& s, std::ptrdiff_t b, double dt) {
  Mat3 d11 = Mat3::Zero(), d12 = Mat3::Zero(), d22 = Mat3::Zero();
  for (int q = s.block_pair_begin[b]; q < s.block_pair_begin[b + 1]; ++q) {
    const int entry = s.block_pair[q], p = entry >> 1;
    if (!has_dashpots(s.implicit, p)) continue;
    const PairBlocks k = blocks_of(s.implicit.pair_matrix[p]);
    d11 += k.k11;
    if (!(entry & 1)) {
      d12 += k.k12;
      d22 += k.k22;
      continue;
    }
    const Vec3 dv = s.position[b] - s.position[s.implicit.blocks[p][0]];
    Mat3 dx;  // [d]x
    dx << 0, -dv.z(), dv.y(), dv.z(), 0, -dv.x(), -dv.y(), dv.x(), 0;
    const Mat3 upper = k.k11 * dx + k.k12;  // top-right of S^T K S
    d12 += upper;
    d22 += dx.transpose() * upper + k.k12.transpose() * dx + k.k22;
  }
  const Mat3& rot = s.rotation[b];
  d11 *= dt;
  d11.diagonal().array() += m.mass_kg[b];
  Mat6 d;
  d.topLeftCorner<3, 3>() = d11;
  d.topRightCorner<3, 3>() = dt * d12;
  d.bottomLeftCorner<3, 3>() = dt * d12.transpose();
  d.bottomRightCorner<3, 3>() = dt * d22 + rot * m.inertia_kg_m2[b].asDiagonal() * rot.transpose();
  return inverse_of_spd(d);
}

// fn(b) on every solved block, in fixed chunks; returns the sums of its N values, each
// in block order within a chunk and over the chunks in chunk order.
template <int N, class Fn>
std::array<double, N> sums_over_solved_blocks(const Model& m, const State& s, Fn&& fn) {
  std::array<std::array<double, N>, kReductionChunks> parts{};
  parallel_chunks(m.block_count, kReductionChunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    std::array<double, N> sum{};
    for (std::ptrdiff_t b = begin; b < end; ++b)
      if (solved(m, s, b)) {
        const std::array<double, N> value = fn(b);
        for (int i = 0; i < N; ++i) sum[i] += value[i];
      }
    parts[k] = sum;
  });
  std::array<double, N> total{};
  for (const std::array<double, N>& p : parts)
    for (int i = 0; i < N; ++i) total[i] += p[i];
  return total;
}

// The same for one value.
template <class Fn>
double for_solved_blocks(const Model& m, const State& s, Fn&& fn) {
  return sums_over_solved_blocks<1>(m, s, [&](std::ptrdiff_t b) { return std::array<double, 1>{fn(b)}; })[0];
}

// The blocks' forces (gathered: gather.cpp), their lists of pairs with dashpots where marked,
// the velocities v* the step gives without the dashpots (prescribed blocks the driver's,
// fixed and frozen blocks are at rest), the preconditioner when `refresh`, and the first
// residual. The preconditioner only steers the iterations (any symmetric positive definite
// one leads to the same solution): refreshed every kPreconditionerRefreshSteps steps, it
// costs a tenth, for a tenth more iterations (model F). The first guess is last step's
// delta, so the first residual dt F_d(v*) - (M + dt C) x = dt F_d(v* + x) - M x is one pass
// over the pairs. Returns r.z, sets *scale2 to the dashpots' impulse at the first guess,
// squared in D^-1's norm, and *contact_power_w to the power the prescribed blocks put in
// against the contacts (gather.cpp's trapezoid rule).
double first_residual(const Model& m, State& s, double dt, bool refresh, double* scale2, double* contact_power_w) {
  ImplicitDamping& w = s.implicit;
  std::vector<Vec6>& x = w.delta;
  // The gather in this pass: a loop of its own cost a team post and a tail a step.
  std::array<double, kStageChunks> power{};
  parallel_chunks(m.block_count, stage_chunks(m.block_count), [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    power[k] = prescribed_power_of_chunk(s, k);
    for (std::ptrdiff_t b = begin; b < end; ++b) {
      gather_block(m, s, b);
      update_dashpot_lists(s, b);
      Vec6& v = w.velocity[b];
      if (solved(m, s, b)) {
        const Mat3& r = s.rotation[b];
        const Vec3& inertia = m.inertia_kg_m2[b];
        Vec3 wb = r.transpose() * s.angular_velocity[b];
        wb += (r.transpose() * s.torque[b] - wb.cross(inertia.cwiseProduct(wb))).cwiseQuotient(inertia) * dt;
        v = stacked(s.velocity[b] + (s.force[b] / m.mass_kg[b] + m.gravity_m_s2) * dt, r * wb);
        w.product[b] = v + x[b];
      } else {
        if (m.motion[b] == Motion::prescribed)  // over the step ahead, as the others' v* + delta
          v = stacked(s.driven_velocity[b], s.driven_angular_velocity[b]);
        else
          v.setZero();
        x[b].setZero();
        w.preconditioned[b].setZero();  // zero where not solved: the products read them
        w.direction[b].setZero();
        w.product[b] = v;
      }
    }
  });
  *contact_power_w = carried_prescribed_power(s);
  for (double p : power) *contact_power_w += p;
  assert(dashpot_lists_are_current(s, m.block_count));
  pair_products_at(m, s, w.product);
  const auto [rz, impulse2] = sums_over_solved_blocks<2>(m, s, [&](std::ptrdiff_t b) {
    if (refresh) w.diagonal[b] = diagonal_inverse(m, s, b, dt);
    w.product[b] = dt * gathered(s, b);  // the dashpots' impulse at the first guess
    w.residual[b] = w.product[b] - mass_times(m, s, b, x[b]);
    w.preconditioned[b] = w.direction[b] = w.diagonal[b] * w.residual[b];
    return std::array<double, 2>{w.residual[b].dot(w.preconditioned[b]), w.product[b].dot(w.diagonal[b] * w.product[b])};
  });
  *scale2 = impulse2;
  return rz;
}

// Preconditioned conjugate gradients on (M + dt C) delta = dt F_d(v*) from the first
// residual, until r.z is below `target`. Returns the iterations; false in *converged when
// it stopped at kDampingSolveMaxIterations.
int conjugate_gradients(const Model& m, State& s, double dt, double rz, double target, bool* converged) {
  ImplicitDamping& w = s.implicit;
  int iterations = 0;
  double beta = 0;  // the first direction is z itself (first_residual)
  while (rz > target && iterations < kDampingSolveMaxIterations) {
    // product = (M + dt C) p, p zero where not solved; p = z + beta p from the second
    // iteration on, computed by the pair pass for its blocks and stored by the block pass.
    const bool update = iterations++ > 0;
    if (update)
      pair_products_at_next_direction(m, s, beta);
    else
      pair_products_at(m, s, w.direction);
    const double pap = for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
      if (update) w.direction[b] = w.preconditioned[b] + beta * w.direction[b];
      w.product[b] = mass_times(m, s, b, w.direction[b]) - dt * gathered(s, b);
      return w.direction[b].dot(w.product[b]);
    });
    if (!(pap > 0)) break;
    const double alpha = rz / pap;
    const double rz_new = for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
      w.delta[b] += alpha * w.direction[b];
      w.residual[b] -= alpha * w.product[b];
      w.preconditioned[b] = w.diagonal[b] * w.residual[b];
      return w.residual[b].dot(w.preconditioned[b]);
    });
    beta = rz_new / rz;
    rz = rz_new;
  }
  *converged = rz <= target;
  return iterations;
}

// The dashpots on the prescribed blocks, at the new velocities v* + delta (their pairs
// only): the power those put in against them, and their share of the work (energy only: the
// order of these sums moves no block). The free blocks' impulse and its work are added as
// each block moves (apply_dashpot_impulse), so here the new velocities are made on the fly.
void book_prescribed(const Model& m, State& s, double dt, DampingSolve& result) {
  const ImplicitDamping& w = s.implicit;
  const auto velocity_after = [&](int b) { return solved(m, s, b) ? Vec6(w.velocity[b] + w.delta[b]) : w.velocity[b]; };
  // Over the pair sides that touch a prescribed block (State::prescribed_entry, in the pair
  // loops' chunks and pair order), summed in chunk order; a loop over every pair to find
  // them took 8 % of a solve of two iterations (model F).
  std::array<double, kStageChunks> parts{};
  parallel_ranges(s.prescribed_entry_begin.data(), static_cast<int>(s.prescribed_entry_begin.size()) - 1,
                  [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
                    double power = 0;  // of the dashpot forces on the prescribed blocks, W
                    for (std::ptrdiff_t q = begin; q < end; ++q) {
                      const auto [entry, block] = s.prescribed_entry[q];
                      const int p = entry >> 1;
                      if (!has_dashpots(w, p)) continue;
                      const auto [a, b] = w.blocks[p];
                      const Vec6 va = velocity_after(a), vb = velocity_after(b);
                      Vec6 on_a = Vec6::Zero(), on_b;
                      pair_resultant(s, va.data(), vb.data(), p, on_a.data(), on_b.data());
                      const Vec6 v = stacked(s.driven_velocity[block], s.driven_angular_velocity[block]);
                      power += ((entry & 1) ? on_b : on_a).dot(v);
                    }
                    parts[k] = power;
                  });
  for (double power : parts) {
    result.prescribed_power_w -= power;
    result.prescribed_work_j += dt * power;
  }
}

}  // namespace

DampingSolve solve_implicit_damping(const Model& m, State& s, double dt) {
  const int nb = m.block_count;
  ImplicitDamping& w = s.implicit;
  const std::size_t np = s.pairs.size();
  w.on_b.resize(np);
  w.on_a.resize(nb);
  w.velocity.resize(nb);
  w.delta.resize(nb, Vec6::Zero());  // a block's entry is kept from step to step
  w.residual.resize(nb);
  w.preconditioned.resize(nb);  // zero where not solved (first_residual's pass sets it)
  w.direction.resize(nb);
  w.product.resize(nb);
  const bool fresh = w.diagonal.size() != static_cast<std::size_t>(nb);  // none yet, nor from a checkpoint
  w.diagonal.resize(nb);

  mark_stale_dashpot_lists(m, s);
  DampingSolve result;
  double scale2 = 0;
  const bool refresh = fresh || s.step % kPreconditionerRefreshSteps == 0;
  const double rz = first_residual(m, s, dt, refresh, &scale2, &result.contact_power_w);
  // Converged when the residual is a small share of the dashpots' impulse.
  const double tolerance = m.options.damping_solve_tolerance;
  const double target = tolerance * tolerance * scale2;
  result.iterations = conjugate_gradients(m, s, dt, rz, target, &result.converged);
  book_prescribed(m, s, dt, result);
  return result;
}

double apply_dashpot_impulse(const Model& m, State& s, double dt, std::ptrdiff_t b) {
  if (!solved(m, s, b)) return 0.0;
  const ImplicitDamping& w = s.implicit;
  const Vec6 impulse = mass_times(m, s, b, w.delta[b]);
  const Vec6 before = stacked(s.velocity[b], s.angular_velocity[b]);
  s.force[b] += linear(impulse) / dt;
  s.torque[b] += angular(impulse) / dt;
  return 0.5 * impulse.dot(before + (w.velocity[b] + w.delta[b]));  // after: v* + delta, as book_prescribed makes it
}

}  // namespace ishibashi
