// The "x y z roll pitch yaw" pose text: reading its six numbers, formatting a pose as it.
#include "hal/config/pose6.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace orthosonar::config {

Pose6Text read_pose6(const std::string& text) {
  Pose6Text p;
  std::istringstream in(text);
  for (double& x : p.v)
    if (!(in >> x) || !std::isfinite(x)) {
      p.fault = Pose6Text::Fault::kNotSixFiniteNumbers;
      return p;
    }
  if (in >> p.rest) p.fault = Pose6Text::Fault::kTrailingText;
  return p;
}

SE3 pose6_se3(const std::array<double, 6>& v) { return se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]); }

std::string format_pose6(const SE3& T) {
  const Vec3 t = T.translation();
  const Vec3 rpy = rpy_from_rotation(T.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", t.x(), t.y(), t.z(), rpy.x(), rpy.y(),
                rpy.z());
  return buf;
}

Result<SE3> parse_pose6(const std::string& text) {
  const Pose6Text p = read_pose6(text);
  switch (p.fault) {
    case Pose6Text::Fault::kNotSixFiniteNumbers:
      return Error{"pose '" + text + "': expected 'x y z roll pitch yaw'"};
    case Pose6Text::Fault::kTrailingText:
      return Error{"pose '" + text + "': trailing text '" + p.rest + "'"};
    case Pose6Text::Fault::kNone:
      break;
  }
  return pose6_se3(p.v);
}

}  // namespace orthosonar::config
