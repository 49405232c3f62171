#include "core/geometry.hpp"

#include <cmath>
#include <numbers>

namespace orthosonar {

double wrap_angle(double a) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  a = std::fmod(a, kTwoPi);
  if (a <= -std::numbers::pi) a += kTwoPi;
  if (a > std::numbers::pi) a -= kTwoPi;
  return a;
}

SE2 SE2::operator*(const SE2& o) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * o.x - s * o.y, y + s * o.x + c * o.y, wrap_angle(theta + o.theta)};
}

Vec2 SE2::operator*(const Vec2& p) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
}

SE2 SE2::inverse() const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {-(c * x + s * y), -(-s * x + c * y), wrap_angle(-theta)};
}

Eigen::Matrix2d SE2::rotation() const {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

Eigen::Matrix3d SE2::matrix() const {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M.topLeftCorner<2, 2>() = rotation();
  M(0, 2) = x;
  M(1, 2) = y;
  return M;
}

Vec3 rpy_from_rotation(const Eigen::Matrix3d& R) {
  // ZYX: R = Rz(yaw) Ry(pitch) Rx(roll).
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return {roll, pitch, yaw};
}

double yaw_of(const Quat& q) { return rpy_from_rotation(q.toRotationMatrix()).z(); }

SE2 se2_from_se3(const SE3& T) {
  return {T.translation().x(), T.translation().y(), rpy_from_rotation(T.rotation()).z()};
}

SE3 se3_from_xyz_rpy(double x, double y, double z, double roll, double pitch, double yaw) {
  SE3 T = SE3::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                Eigen::AngleAxisd(roll, Vec3::UnitX()))
                   .toRotationMatrix();
  T.translation() = Vec3(x, y, z);
  return T;
}

SE3 se3_from_se2(const SE2& T, double z, double roll, double pitch) {
  return se3_from_xyz_rpy(T.x, T.y, z, roll, pitch, T.theta);
}

SE3 interpolate(const SE3& a, const SE3& b, double s) {
  SE3 out = SE3::Identity();
  out.translation() = (1.0 - s) * a.translation() + s * b.translation();
  const Quat qa(a.rotation()), qb(b.rotation());
  out.linear() = qa.slerp(s, qb).toRotationMatrix();
  return out;
}

SE2 interpolate(const SE2& a, const SE2& b, double s) {
  const double dtheta = wrap_angle(b.theta - a.theta);
  return {(1.0 - s) * a.x + s * b.x, (1.0 - s) * a.y + s * b.y, wrap_angle(a.theta + s * dtheta)};
}

Vec3 spherical_to_cartesian(double range_m, double bearing_rad, double elevation_rad) {
  const double cphi = std::cos(elevation_rad);
  return {range_m * cphi * std::cos(bearing_rad), range_m * cphi * std::sin(bearing_rad),
          range_m * std::sin(elevation_rad)};
}

Vec3 cartesian_to_spherical(const Vec3& p) {
  const double r = p.norm();
  const double theta = std::atan2(p.y(), p.x());
  const double phi = r > 0.0 ? std::asin(std::clamp(p.z() / r, -1.0, 1.0)) : 0.0;
  return {r, theta, phi};
}

}  // namespace orthosonar
