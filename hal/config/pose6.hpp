// The "x y z roll pitch yaw" pose text (metres, radians): how fixture metadata, the run and
// simulator configurations and the import's topic map write a mount or an extrinsic.
#pragma once

#include <array>
#include <string>

#include "core/geometry.hpp"
#include "core/result.hpp"

namespace orthosonar::config {

// The six numbers of a pose text, or what is wrong with it (each caller words its error).
struct Pose6Text {
  enum class Fault { kNone, kNotSixFiniteNumbers, kTrailingText };
  std::array<double, 6> v{};  // x y z roll pitch yaw, as read (valid when fault is kNone)
  Fault fault = Fault::kNone;
  std::string rest;           // kTrailingText: the first word after the sixth number
};
Pose6Text read_pose6(const std::string& text);

// The pose of six numbers (metres, radians).
SE3 pose6_se3(const std::array<double, 6>& v);

// "x y z roll pitch yaw" with 17 significant digits (lossless), and back.
std::string format_pose6(const SE3& T);
Result<SE3> parse_pose6(const std::string& text);

}  // namespace orthosonar::config
