#pragma once
// Definition texts of the message types orthosonar imports and exports (issue 18), as
// their packages publish them: the authors' stack (sonar_oculus/OculusPing,
// OculusPingUncompressed, rti_dvl/DVL, bar30_depth/Depth, kvh_gyro/gyro), the community standard
// (marine_acoustic_msgs/ProjectedSonarImage) and the common ROS types (sensor_msgs/Imu,
// sensor_msgs/FluidPressure, geometry_msgs/TwistWithCovarianceStamped,
// geometry_msgs/PoseStamped, sensor_msgs/Image, sensor_msgs/CompressedImage). Each text is
// complete (dependencies in "MSG:" sections), in the ROS 1 form (bag connection records,
// ros1msg schemas) and the ROS 2 form (ros2msg schemas: builtin_interfaces/Time stamps,
// no Header seq).
#include <string>
#include <string_view>
#include <vector>

#include "replay/ros/ros_msg.hpp"

namespace orthosonar::replay::rosmsg {

struct KnownType {
  std::string_view name;  // "pkg/Type"
  std::string_view ros1;  // full ROS 1 definition text
  std::string_view ros2;  // full ROS 2 definition text
};

// nullptr when the type is not one of ours.
const KnownType* known_type(std::string_view name);
const std::vector<KnownType>& known_types();
// The definition text of a known type in a dialect (empty when unknown).
std::string_view definition(std::string_view name, Dialect dialect);
// The ROS 1 MD5 sum of a known type (computed from its ROS 1 text; empty when unknown).
std::string md5_of(std::string_view name);

}  // namespace orthosonar::replay::rosmsg
