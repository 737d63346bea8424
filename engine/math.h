// Small linear-algebra vocabulary shared by every stage (SI units throughout).
#pragma once
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

}  // namespace ishibashi
