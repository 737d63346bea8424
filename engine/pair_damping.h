// A pair's dashpots as one symmetric 6x6 matrix K (N s/m, N s, N m s), for the implicit
// dashpots (Damping::implicit): the force on b and its moment about x_a are
// (F, T) = -K (v0, w), for the relative motion of b against a given as the velocity v0 of
// the point at x_a and the angular velocity w. A sub-contact at lever r from x_a moves at
// u = v0 + w x r = J (v0, w), J = [I, -[r]x], and pushes with -C u, C = cs I + (cn - cs) n n^T,
// so K = sum J^T C J = sum cs [[I, -[r]x], [[r]x, |r|^2 I - r r^T]] + (cn - cs) g g^T,
// g = (n, r x n).
//
// Every sub-contact of a pair has the pair's one normal n (its manifold's, narrowphase.h),
// so K follows from the weighted moments of the levers alone: with c1 = cn - cs,
//   sum c1 g g^T = [[S1 n n^T, n (P1 x n)^T], [(P1 x n) n^T, [n]x Q1 [n]x^T]],
// S1 = sum c1, P1 = sum c1 r, Q1 = sum c1 r r^T, and the shear part from the same three
// moments of cs: ten sums per constant (1 + 3 + 6) for each sub-contact, where
// the pair matrices are summed once a step over every sub-contact.
#pragma once
#include "engine/math.h"
#include "engine/state.h"

namespace ishibashi {

// Where (i, j) of a symmetric 6x6 sits in Sym6.
constexpr int kSymIndex[6][6] = {{0, 1, 3, 6, 10, 15},   {1, 2, 4, 7, 11, 16},     {3, 4, 5, 8, 12, 17},
                                 {6, 7, 8, 9, 13, 18},   {10, 11, 12, 13, 14, 19}, {15, 16, 17, 18, 19, 20}};

class PairDampingSum {
 public:
  // A dashpot with constants cn, cs (N s/m) at lever r from x_a (normal: the pair's).
  void add(double cn, double cs, const Vec3& r) {
    normal_.add(cn - cs, r);
    shear_.add(cs, r);
  }

  // K for the pair's normal n (unit), written straight into its lower triangle.
  Sym6 matrix(const Vec3& n) const {
    const Mat3 bend = cross_square(n, normal_.second);  // [n]x Q1 [n]x^T
    const double* q = shear_.second;                    // Q of cs (lower triangle)
    const double trace = q[0] + (q[2] + q[5]);  // Eigen's trace() order (bit for bit with it)
    const Vec3 p1n = normal_.first.cross(n);
    Mat3 lever_cross;  // [sum cs r]x
    const Vec3& l = shear_.first;
    lever_cross << 0, -l.z(), l.y(), l.z(), 0, -l.x(), -l.y(), l.x(), 0;
    Sym6 k;
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
#pragma GCC unroll 3
      for (int j = 0; j <= i; ++j) {
        const double diagonal = i == j ? 1.0 : 0.0;
        k.v[kSymIndex[i][j]] = normal_.sum * n[i] * n[j] + diagonal * shear_.sum;
        k.v[kSymIndex[3 + i][3 + j]] = bend(i, j) + diagonal * trace - q[kSym3[i][j]];
      }
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) k.v[kSymIndex[3 + i][j]] = p1n[i] * n[j] + lever_cross(i, j);
    }
    return k;
  }

 private:
  // sum c, sum c r (m), sum c r r^T (m^2, lower triangle: xx, yx, yy, zx, zy, zz).
  struct Moments {
    double sum = 0;
    Vec3 first = Vec3::Zero();
    double second[6] = {};
    void add(double c, const Vec3& r) {
      sum += c;
      const Vec3 cr = c * r;
      first += cr;
      second[0] += cr.x() * r.x();
      second[1] += cr.y() * r.x();
      second[2] += cr.y() * r.y();
      second[3] += cr.z() * r.x();
      second[4] += cr.z() * r.y();
      second[5] += cr.z() * r.z();
    }
  };
  // Where (i, j) of a symmetric 3x3 sits in Moments::second.
  static constexpr int kSym3[3][3] = {{0, 1, 3}, {1, 2, 4}, {3, 4, 5}};
  // [n]x Q [n]x^T for Q symmetric (lower triangle q), lower triangle: ([n]x Q) first, then
  // times [n]x^T, each entry summed in the order of the full 3x3 products without their
  // terms in [n]x's zero diagonal (a third of the work).
  static Mat3 cross_square(const Vec3& n, const double* q) {
    const double nx = n.x(), ny = n.y(), nz = n.z();
    double t[3][3];  // [n]x Q
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const double q0 = q[kSym3[0][j]], q1 = q[kSym3[1][j]], q2 = q[kSym3[2][j]];
      t[0][j] = -nz * q1 + ny * q2;
      t[1][j] = nz * q0 + -nx * q2;
      t[2][j] = -ny * q0 + nx * q1;
    }
    Mat3 b;
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      b(i, 0) = t[i][1] * -nz + t[i][2] * ny;
      b(i, 1) = t[i][0] * nz + t[i][2] * -nx;
      b(i, 2) = t[i][0] * -ny + t[i][1] * nx;
    }
    return b;
  }
  Moments normal_, shear_;
};

}  // namespace ishibashi
