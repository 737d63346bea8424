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
    Mat3 cross_n;  // [n]x
    cross_n << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
    const Mat3 bend = cross_n * normal_.second_moment() * cross_n.transpose();
    const Mat3 shear_second = shear_.second_moment();
    const double trace = shear_second.trace();
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
        k.v[kSymIndex[3 + i][3 + j]] = bend(i, j) + diagonal * trace - shear_second(i, j);
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
    Mat3 second_moment() const {
      Mat3 q;
      q << second[0], second[1], second[3], second[1], second[2], second[4], second[3], second[4], second[5];
      return q;
    }
  };
  Moments normal_, shear_;
};

}  // namespace ishibashi
