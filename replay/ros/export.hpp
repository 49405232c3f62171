#pragma once
// `orthosonar export`: a fixture as a ROS 1 bag or a ROS 2 MCAP recording, so any ROS stack
// (the authors' included) runs on our missions (docs/IMPORT.md).
//   --sonar-type oculus     the authors' topics and types: sonar_oculus/OculusPing (JPEG,
//                           quality 80, as their driver publishes) or OculusPingUncompressed
//                           (--image raw), sensor_msgs/Imu, rti_dvl/DVL, bar30_depth/Depth
//   --sonar-type projected  the community's: marine_acoustic_msgs/ProjectedSonarImage,
//                           sensor_msgs/Imu, geometry_msgs/TwistWithCovarianceStamped,
//                           sensor_msgs/FluidPressure
// Truth poses go to /orthosonar/truth (geometry_msgs/PoseStamped), a fibre-optic gyro's
// readings to /gyro (the authors' kvh_gyro/gyro, delta angles: rates are made angles over
// the interval each covers, export.cpp GyroDeltas); labels stay behind.
// Beside OUT, OUT's stem + ".topics.yaml" maps the written topics back (mounts, the gyro's
// included, the latitude and device ids), so `orthosonar import OUT --map that.yaml`
// restores the fixture's events (a gyro reading's packet counter and temperature excepted).
#include <cstdint>
#include <map>
#include <string>

#include "core/result.hpp"
#include "replay/fixture/fixture.hpp"

namespace orthosonar::replay::ros {

enum class ExportTarget { kRos1Bag, kRos2Mcap };
enum class SonarType { kOculus, kProjected };

struct ExportOptions {
  ExportTarget target = ExportTarget::kRos1Bag;
  SonarType sonar = SonarType::kOculus;
  bool jpeg = true;               // oculus: CompressedImage JPEG (false: OculusPingUncompressed)
  int jpeg_quality = 80;
  std::string compression;        // bag: none (default), bz2, lz4; MCAP: zstd (default), none
  bool write_topics_yaml = true;
  uint64_t bag_chunk_bytes = 768 * 1024;  // as rosbag record's default chunk threshold
};

struct ExportReport {
  std::map<std::string, uint64_t> messages;  // per topic
  std::string topics_yaml;                   // path written ("" when not)
  uint64_t skipped_labels = 0;
  replay::RecoveryReport input_recovery;     // whether the fixture was whole (cut_input_warning)
};

// Errors name the fixture (and byte offset) or the event that cannot be expressed (a
// 16-bit ping as JPEG, a stamp outside the ROS time range).
Result<ExportReport> export_fixture(const std::string& fixture, const std::string& out, const ExportOptions& options);

// Where export writes the companion topics.yaml for `out`.
std::string topics_yaml_path(const std::string& out);

}  // namespace orthosonar::replay::ros
