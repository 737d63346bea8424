// Small linear-algebra vocabulary shared by every stage (SI units throughout).
#pragma once
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace ishibashi {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;  // 3 translations, 3 rotations of a block
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaterniond;

// Quaternion of a rotation by the vector `rotation_rad` (axis * angle).
inline Quat quat_from_rotation_vector(const Vec3& rotation_rad) {
  const double angle = rotation_rad.norm();
  if (angle < 1e-300) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, rotation_rad / angle));
}

// The inverse of a symmetric positive definite 6x6 matrix (only its lower triangle is
// read), through its Cholesky factor L: D^-1 = L^-T L^-1, exactly symmetric. Written out
// because Eigen's LLT solve with a matrix right-hand side goes through its generic
// kernels (3 % of a cracked bridge's implicit step, refreshing the preconditioner).
// NaN where d is not positive definite (the square root of a negative pivot).
inline Mat6 inverse_of_spd(const Mat6& d) {
  double l[6][6] = {};  // L, lower
  for (int j = 0; j < 6; ++j) {
    double diagonal = d(j, j);
    for (int k = 0; k < j; ++k) diagonal -= l[j][k] * l[j][k];
    l[j][j] = std::sqrt(diagonal);
    for (int i = j + 1; i < 6; ++i) {
      double v = d(i, j);
      for (int k = 0; k < j; ++k) v -= l[i][k] * l[j][k];
      l[i][j] = v / l[j][j];
    }
  }
  double li[6][6] = {};  // L^-1, lower, column by column
  for (int j = 0; j < 6; ++j) {
    li[j][j] = 1.0 / l[j][j];
    for (int i = j + 1; i < 6; ++i) {
      double v = 0.0;
      for (int k = j; k < i; ++k) v -= l[i][k] * li[k][j];
      li[i][j] = v / l[i][i];
    }
  }
  Mat6 inverse;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j <= i; ++j) {
      double v = 0.0;
      for (int k = i; k < 6; ++k) v += li[k][i] * li[k][j];
      inverse(i, j) = inverse(j, i) = v;
    }
  return inverse;
}

}  // namespace ishibashi
