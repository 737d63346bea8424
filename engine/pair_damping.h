// A pair's dashpots as one symmetric 6x6 matrix K (N s/m, N s, N m s), for the implicit
// dashpots (Damping::implicit): the force on b and its moment about x_a are
// (F, T) = -K (v0, w), for the relative motion of b against a given as the velocity v0 of
// the point at x_a and the angular velocity w. A sub-contact at lever r from x_a moves at
// u = v0 + w x r = J (v0, w), J = [I, -[r]x], and pushes with -C u, C = cs I + (cn - cs) n n^T,
// so K = sum J^T C J = sum cs [[I, -[r]x], [[r]x, |r|^2 I - r r^T]] + (cn - cs) g g^T,
// g = (n, r x n). The contact law sums it as it goes (its sub-contacts are in registers
// there), on scalars: it is on the hot path.
#pragma once
#include "engine/math.h"
#include "engine/state.h"

namespace ishibashi {

// Where (i, j) of a symmetric 6x6 sits in Sym6.
constexpr int kSymIndex[6][6] = {{0, 1, 3, 6, 10, 15},   {1, 2, 4, 7, 11, 16},     {3, 4, 5, 8, 12, 17},
                                 {6, 7, 8, 9, 13, 18},   {10, 11, 12, 13, 14, 19}, {15, 16, 17, 18, 19, 20}};

class PairDampingSum {
 public:
  // A dashpot with constants cn, cs (N s/m) at lever r from x_a, normal n.
  void add(double cn, double cs, const Vec3& n, const Vec3& r) {
    const Vec3 rn = r.cross(n);
    const double g[6] = {n.x(), n.y(), n.z(), rn.x(), rn.y(), rn.z()};
    const double c1 = cn - cs;
#pragma GCC unroll 6
    for (int row = 0; row < 6; ++row) {
      const double cg = c1 * g[row];
#pragma GCC unroll 6
      for (int col = 0; col <= row; ++col) rank_one_[kSymIndex[row][col]] += cg * g[col];
    }
    cs_sum_ += cs;
#pragma GCC unroll 3
    for (int row = 0; row < 3; ++row) {
      lever_[row] += cs * r[row];
#pragma GCC unroll 3
      for (int col = 0; col <= row; ++col) rr_[kSymIndex[row][col]] += cs * r[row] * r[col];
    }
  }

  Sym6 matrix() const {
    Sym6 k;
    for (int at = 0; at < 21; ++at) k.v[at] = rank_one_[at];
    const double trace = rr_[0] + rr_[2] + rr_[5];
    for (int row = 0; row < 3; ++row) {
      k.v[kSymIndex[row][row]] += cs_sum_;
      for (int col = 0; col <= row; ++col)
        k.v[kSymIndex[3 + row][3 + col]] += (row == col ? trace : 0.0) - rr_[kSymIndex[row][col]];
    }
    // Below the diagonal, [sum cs r]x: its rows are (0, -z, y), (z, 0, -x), (-y, x, 0).
    k.v[kSymIndex[3][1]] -= lever_[2];
    k.v[kSymIndex[3][2]] += lever_[1];
    k.v[kSymIndex[4][0]] += lever_[2];
    k.v[kSymIndex[4][2]] -= lever_[0];
    k.v[kSymIndex[5][0]] -= lever_[1];
    k.v[kSymIndex[5][1]] += lever_[0];
    return k;
  }

 private:
  double rank_one_[21] = {};  // sum (cn - cs) g g^T, Sym6 order
  double rr_[6] = {};         // sum cs r r^T, lower triangle in Sym6 order
  double lever_[3] = {};      // sum cs r
  double cs_sum_ = 0;
};

}  // namespace ishibashi
