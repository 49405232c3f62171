#pragma once
// SE(2) and SE(3) helpers on Eigen. Frames follow REP-103 (x forward, y left, z up).
// Transforms are named by their frames: T_W_V maps points from V into W, and
// T_A_C = T_A_B * T_B_C.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>

namespace orthosonar {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// Radians per degree.
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;
using SE3 = Eigen::Isometry3d;

// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

// A planar rigid transform: rotation by theta (rad, counter-clockwise) then translation.
struct SE2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  static SE2 identity() { return {}; }
  SE2 operator*(const SE2& o) const;            // composition
  Vec2 operator*(const Vec2& p) const;          // acts on a point
  SE2 inverse() const;
  Eigen::Matrix3d matrix() const;
  Eigen::Matrix2d rotation() const;
  Vec2 translation() const { return {x, y}; }
};

// The SE(2) part of an SE(3) pose: x, y and yaw (z and roll/pitch dropped).
SE2 se2_from_se3(const SE3& T);
// An SE(3) pose from planar x, y, yaw plus z, roll and pitch (rad). Rotation = Rz(yaw) Ry(pitch) Rx(roll).
SE3 se3_from_se2(const SE2& T, double z, double roll, double pitch);
SE3 se3_from_xyz_rpy(double x, double y, double z, double roll, double pitch, double yaw);
// Roll, pitch, yaw (rad) of a rotation, ZYX convention.
Vec3 rpy_from_rotation(const Eigen::Matrix3d& R);
double yaw_of(const Quat& q);

// Interpolation at s in [0, 1]: linear in translation, slerp in rotation (SPEC §2).
SE3 interpolate(const SE3& a, const SE3& b, double s);
SE2 interpolate(const SE2& a, const SE2& b, double s);

// Spherical to Cartesian (paper Eq. 1): X = R cosφ cosθ, Y = R cosφ sinθ, Z = R sinφ.
Vec3 spherical_to_cartesian(double range_m, double bearing_rad, double elevation_rad);
// Inverse of Eq. 1: (R, θ, φ).
Vec3 cartesian_to_spherical(const Vec3& p);

}  // namespace orthosonar
