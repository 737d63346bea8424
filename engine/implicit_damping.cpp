// Implicit dashpots (Damping::implicit, issue 28): the contact law applies the springs
// only; this stage finds the velocities at the end of the step with every dashpot
// evaluated there, backward Euler in the damping,
//   (M + dt C) v_new = M v* + (dt C_p v_p),
// with v* the velocities semi-implicit Euler gives without the dashpots, C the dashpot
// matrix of the free blocks' sub-contacts and v_p the prescribed blocks' velocities. Its
// unknown is the change the dashpots make, delta = v_new - v* (6 per free block), found
// by conjugate gradients preconditioned with each block's own 6x6 diagonal block of
// M + dt C, matrix-free: a product is one pass over the pairs' 6x6 dashpot matrices
// (pair_damping.h, summed from the sub-contacts once a step) and a gather.
// Backward Euler never amplifies a damped mode, so dt is limited by the springs alone
// (explicit dashpots with h = 1 on a block held by many joints: a tenth of that or less).
// The change is handed to integrate() as the force M delta / dt.
// Every sum runs in fixed chunks in a fixed order: the result is the same for any team.
#include <array>
#include <cmath>

#include "engine/pair_damping.h"
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

Vec3 linear(const Vec6& v) { return v.head<3>(); }
Vec3 angular(const Vec6& v) { return v.tail<3>(); }

bool solved(const Model& m, const State& s, std::ptrdiff_t b) { return m.motion[b] == Motion::free && !s.left_model[b]; }

// Block b's mass matrix applied to x (world frame): m x_v and R I R^T x_w.
Vec6 mass_times(const Model& m, const State& s, std::ptrdiff_t b, const Vec6& x) {
  const Mat3& r = s.rotation[b];
  Vec6 y;
  y << m.mass_kg[b] * linear(x), r * m.inertia_kg_m2[b].cwiseProduct(r.transpose() * angular(x));
  return y;
}

Vec6 times(const Sym6& k, const Vec6& x) {
  double y[6];
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) {
    double sum = 0;
#pragma GCC unroll 6
    for (int j = 0; j < 6; ++j) sum += k.v[kSymIndex[i][j]] * x[j];
    y[i] = sum;
  }
  return Vec6(y[0], y[1], y[2], y[3], y[4], y[5]);
}

Mat6 full(const Sym6& k) {
  Mat6 f;
  int at = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j <= i; ++j, ++at) f(i, j) = f(j, i) = k.v[at];
  return f;
}

// Resultants of the dashpot forces of the pair in slot k at block velocities x (nb, world
// frame): the force on b (N) and the moments on a about x_a and on b about x_b (N m).
struct PairResultant {
  Vec3 force, moment_a, moment_b;
};
// Inlined into both passes that call it (GCC would not): 7 % of the solve on model F.
inline __attribute__((always_inline)) PairResultant pair_dashpots(const ImplicitDamping& w, const std::vector<Vec6>& x,
                                                                  std::ptrdiff_t k) {
  const int a = w.blocks[k][0], b = w.blocks[k][1];
  const Vec3& d = w.lever[k];
  Vec6 relative;  // v0 = v_b + w_b x (x_a - x_b) - v_a, w = w_b - w_a
  relative << linear(x[b]) - linear(x[a]) - angular(x[b]).cross(d), angular(x[b]) - angular(x[a]);
  const Vec6 f = -times(w.pair_matrix[k], relative);
  return {linear(f), -angular(f), angular(f) - d.cross(linear(f))};
}

// Every pair's dashpot resultants at x, in State's pair arrays (pairs without
// sub-contacts keep the zeros the contact law wrote). With `assemble`, the pair matrices
// are first summed from the sub-contacts' dashpots as the contact law left them this
// step: none where a sub-contact is open, no shear one where it slides and no normal one
// where a softening bond is held at its tensile strength (MODEL.md section 3).
void dashpot_resultants(State& s, const std::vector<Vec6>& x, bool assemble = false) {
  ImplicitDamping& w = s.implicit;
  parallel_chunks(static_cast<std::ptrdiff_t>(w.pairs.size()), kReductionChunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int) {
    for (std::ptrdiff_t k = begin; k < end; ++k) {
      const int pi = w.pairs[k];
      if (assemble) {
        const SubContacts& c = s.contacts;
        const Pair& pair = s.pairs[pi];
        PairDampingSum sum;
        for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
          const std::uint8_t flags = c.flags[i];
          if (flags & SubContactFlag::open) continue;
          const double cn = (flags & SubContactFlag::pulling) ? 0.0 : c.normal_damping_n_s_m[i];
          const double cs = (flags & SubContactFlag::sliding) ? 0.0 : c.shear_damping_n_s_m[i];
          sum.add(cn, cs, c.point[i] - s.position[pair.a]);
        }
        w.pair_matrix[k] = sum.matrix(c.normal[pair.sub_begin]);
        w.blocks[k] = {pair.a, pair.b};
        w.lever[k] = s.position[pair.b] - s.position[pair.a];
      }
      const PairResultant r = pair_dashpots(w, x, k);
      s.pair_force_n[pi] = r.force;
      s.pair_moment_nm[2 * pi] = r.moment_a;
      s.pair_moment_nm[2 * pi + 1] = r.moment_b;
    }
  });
}

// The gathered dashpot force and moment on block b from the pair arrays (N, N m).
Vec6 gathered(const State& s, std::ptrdiff_t b) {
  Vec6 f = Vec6::Zero();
  for (int q = s.block_pair_begin[b]; q < s.block_pair_begin[b + 1]; ++q) {
    const int entry = s.block_pair[q];  // 2p: b is the pair's a, 2p + 1: its b
    if (entry & 1)
      f.head<3>() += s.pair_force_n[entry >> 1];
    else
      f.head<3>() -= s.pair_force_n[entry >> 1];
    f.tail<3>() += s.pair_moment_nm[entry];
  }
  return f;
}

// Block b's diagonal block of M + dt C, inverted. Its pairs' matrices: as they are where b
// is a (its velocity enters v0 and w with a minus sign), and S^T K S where b is b, with
// S = [[I, [d]x], [0, I]] mapping (v_b, w_b) to (v0, w), d = x_b - x_a.
Mat6 diagonal_inverse(const Model& m, const State& s, std::ptrdiff_t b, double dt) {
  Mat6 d = Mat6::Zero();
  for (int q = s.block_pair_begin[b]; q < s.block_pair_begin[b + 1]; ++q) {
    const int entry = s.block_pair[q];
    const int slot = s.implicit.slot[entry >> 1];
    if (slot < 0) continue;
    const Mat6 k = full(s.implicit.pair_matrix[slot]);
    if (!(entry & 1)) {
      d += k;
      continue;
    }
    const Vec3& dv = s.implicit.lever[slot];
    Mat3 dx;  // [d]x
    dx << 0, -dv.z(), dv.y(), dv.z(), 0, -dv.x(), -dv.y(), dv.x(), 0;
    const Mat3 k11 = k.topLeftCorner<3, 3>(), k12 = k.topRightCorner<3, 3>(), k22 = k.bottomRightCorner<3, 3>();
    const Mat3 upper = k11 * dx + k12;  // top-right of S^T K S
    d.topLeftCorner<3, 3>() += k11;
    d.topRightCorner<3, 3>() += upper;
    d.bottomLeftCorner<3, 3>() += upper.transpose();
    d.bottomRightCorner<3, 3>() += dx.transpose() * upper + k12.transpose() * dx + k22;
  }
  d *= dt;
  const Mat3& rot = s.rotation[b];
  d.topLeftCorner<3, 3>().diagonal().array() += m.mass_kg[b];
  d.bottomRightCorner<3, 3>() += rot * m.inertia_kg_m2[b].asDiagonal() * rot.transpose();
  return d.llt().solve(Mat6::Identity());
}

// fn(b) on every solved block, in fixed chunks; returns the sum of its values in chunk order.
template <class Fn>
double for_solved_blocks(const Model& m, const State& s, Fn&& fn) {
  std::array<double, kReductionChunks> parts{};
  parallel_chunks(m.block_count, kReductionChunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    double sum = 0;
    for (std::ptrdiff_t b = begin; b < end; ++b)
      if (solved(m, s, b)) sum += fn(b);
    parts[k] = sum;
  });
  double total = 0;
  for (double p : parts) total += p;
  return total;
}

// The velocities v* integrate() gives without the dashpots (prescribed blocks keep theirs,
// fixed and frozen blocks are at rest), the preconditioner when `refresh`, and the first
// residual. The preconditioner only steers the iterations (any symmetric positive definite
// one leads to the same solution): refreshed every kPreconditionerRefreshSteps steps, it
// costs a tenth, for a tenth more iterations (model F). The first guess is last step's
// delta, so the first residual dt F_d(v*) - (M + dt C) x = dt F_d(v* + x) - M x is one pass
// over the pairs. Returns r.z and sets *scale2 to the dashpots' impulse at the first
// guess, squared in D^-1's norm.
double first_residual(const Model& m, State& s, double dt, bool refresh, double* scale2) {
  ImplicitDamping& w = s.implicit;
  std::vector<Vec6>& x = w.delta;
  parallel_for(m.block_count, [&](std::ptrdiff_t b) {
    Vec6& v = w.velocity[b];
    if (solved(m, s, b)) {
      const Mat3& r = s.rotation[b];
      const Vec3& inertia = m.inertia_kg_m2[b];
      Vec3 wb = r.transpose() * s.angular_velocity[b];
      wb += (r.transpose() * s.torque[b] - wb.cross(inertia.cwiseProduct(wb))).cwiseQuotient(inertia) * dt;
      v << s.velocity[b] + (s.force[b] / m.mass_kg[b] + m.gravity_m_s2) * dt, r * wb;
      w.product[b] = v + x[b];
    } else {
      if (m.motion[b] == Motion::prescribed)
        v << s.velocity[b], s.angular_velocity[b];
      else
        v.setZero();
      x[b].setZero();
      w.product[b] = v;
    }
  });
  dashpot_resultants(s, w.product, /*assemble=*/true);
  const double rz = for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
    if (refresh) w.diagonal[b] = diagonal_inverse(m, s, b, dt);
    w.product[b] = dt * gathered(s, b);  // the dashpots' impulse at the first guess
    w.residual[b] = w.product[b] - mass_times(m, s, b, x[b]);
    w.preconditioned[b] = w.direction[b] = w.diagonal[b] * w.residual[b];
    return w.residual[b].dot(w.preconditioned[b]);
  });
  *scale2 = for_solved_blocks(m, s, [&](std::ptrdiff_t b) { return w.product[b].dot(w.diagonal[b] * w.product[b]); });
  return rz;
}

// Preconditioned conjugate gradients on (M + dt C) delta = dt F_d(v*) from the first
// residual, until r.z is below `target`. Returns the iterations; false in *converged when
// it stopped at kDampingSolveMaxIterations.
int conjugate_gradients(const Model& m, State& s, double dt, double rz, double target, bool* converged) {
  ImplicitDamping& w = s.implicit;
  int iterations = 0;
  while (rz > target && iterations < kDampingSolveMaxIterations) {
    ++iterations;
    // product = (M + dt C) p, p zero where not solved.
    dashpot_resultants(s, w.direction);
    const double pap = for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
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
    const double beta = rz_new / rz;
    rz = rz_new;
    for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
      w.direction[b] = w.preconditioned[b] + beta * w.direction[b];
      return 0.0;
    });
  }
  *converged = rz <= target;
  return iterations;
}

// The dashpots' impulse on the free blocks is M delta: the force integrate() takes, and its
// work over the step at the mean of the velocities before and after (the form in which
// the step balances kinetic energy). The dashpots on the prescribed blocks, at the new
// velocities (their pairs only): the power those put in against them, and their share of
// the work.
void book(const Model& m, State& s, double dt, DampingSolve& result) {
  ImplicitDamping& w = s.implicit;
  result.work_j = for_solved_blocks(m, s, [&](std::ptrdiff_t b) {
    const Vec6 impulse = mass_times(m, s, b, w.delta[b]);
    Vec6 before;
    before << s.velocity[b], s.angular_velocity[b];
    w.velocity[b] += w.delta[b];
    s.force[b] += linear(impulse) / dt;
    s.torque[b] += angular(impulse) / dt;
    return 0.5 * impulse.dot(before + w.velocity[b]);
  });
  for (int b = 0; b < m.block_count; ++b) {
    if (m.motion[b] != Motion::prescribed) continue;
    Vec6 f = Vec6::Zero();
    for (int q = s.block_pair_begin[b]; q < s.block_pair_begin[b + 1]; ++q) {
      const int entry = s.block_pair[q];
      const int slot = w.slot[entry >> 1];
      if (slot < 0) continue;
      const PairResultant r = pair_dashpots(w, w.velocity, slot);
      f.head<3>() += (entry & 1) ? r.force : Vec3(-r.force);
      f.tail<3>() += (entry & 1) ? r.moment_b : r.moment_a;
    }
    const double power = linear(f).dot(s.velocity[b]) + angular(f).dot(s.angular_velocity[b]);
    result.prescribed_power_w -= power;
    result.work_j += dt * power;
  }
}

}  // namespace

DampingSolve solve_implicit_damping(const Model& m, State& s, double dt) {
  const int nb = m.block_count;
  ImplicitDamping& w = s.implicit;
  w.pairs.clear();
  w.slot.resize(s.pairs.size());
  for (std::size_t pi = 0; pi < s.pairs.size(); ++pi) {
    w.slot[pi] = s.pairs[pi].sub_count > 0 ? static_cast<int>(w.pairs.size()) : -1;
    if (s.pairs[pi].sub_count > 0) w.pairs.push_back(static_cast<int>(pi));
  }
  w.blocks.resize(w.pairs.size());
  w.lever.resize(w.pairs.size());
  w.pair_matrix.resize(w.pairs.size());
  w.velocity.resize(nb);
  w.delta.resize(nb, Vec6::Zero());  // a block's entry is kept from step to step
  w.residual.resize(nb);
  w.preconditioned.resize(nb);
  w.direction.assign(nb, Vec6::Zero());  // zero where not solved: the products read it
  w.product.resize(nb);
  const bool fresh = w.diagonal.size() != static_cast<std::size_t>(nb);  // none yet, nor from a checkpoint
  w.diagonal.resize(nb);

  DampingSolve result;
  double scale2 = 0;
  const double rz = first_residual(m, s, dt, fresh || s.step % kPreconditionerRefreshSteps == 0, &scale2);
  // Converged when the residual is a small share of the dashpots' impulse.
  const double target = kDampingSolveTolerance * kDampingSolveTolerance * scale2;
  result.iterations = conjugate_gradients(m, s, dt, rz, target, &result.converged);
  book(m, s, dt, result);
  return result;
}

}  // namespace ishibashi
