#pragma once
// `orthosonar import`: a ROS 1 bag or a ROS 2 (or ROS 1) MCAP recording to a fixture
// (docs/IMPORT.md). Topics feed roles through a TopicMap; each role's message types:
//   sonars  sonar_oculus/OculusPing (JPEG/PNG image), sonar_oculus/OculusPingUncompressed,
//           marine_acoustic_msgs/ProjectedSonarImage
//   imu     sensor_msgs/Imu
//   dvl     rti_dvl/DVL, geometry_msgs/TwistWithCovarianceStamped, geometry_msgs/TwistStamped
//   depth   bar30_depth/Depth, sensor_msgs/FluidPressure
//   truth   geometry_msgs/PoseStamped, nav_msgs/Odometry (optional)
//   gyro    kvh_gyro/gyro (optional; the authors' fibre-optic gyro: delta angles)
// The fixture's events are the recording's messages in (stamp, channel, sequence) order
// with sequences numbered per channel in stamp order; its bytes are a pure function of the
// input file and the map (importing twice gives identical files).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/ros/topic_map.hpp"

namespace orthosonar::replay::ros {

struct TopicInfo {
  std::string topic;
  std::string type;              // normalised "pkg/Type"
  std::string encoding;          // "ros1" or "cdr"
  uint64_t count = 0;
  uint64_t first_ns = 0, last_ns = 0;  // receive (log) times
  std::optional<Role> role;      // the role the map gives it (none: ignored)
  std::string note;              // why it cannot be imported as that role, or ""
  double rate_hz() const;
};

struct InputSummary {
  std::string path;
  std::string format;            // "ros1 bag" or "mcap"
  uint64_t bytes = 0;
  std::vector<TopicInfo> topics;  // by topic name
  bool complete = true;          // false: a truncated file, read up to `recovery`
  std::string recovery;          // what was kept and where reading stopped
};

// Reads the whole file once (no message decoding) and applies the map.
Result<InputSummary> list_input(const std::string& path, const TopicMap& map);

struct ImportOptions {
  TopicMap map = default_topic_map();
  // zstd level 1: twice the import speed of the recorder's level 3 for 0.2 % more bytes
  // on sonar images (docs/BENCHMARKS.md); a replay reads either the same.
  WriterOptions writer = {.compress = true, .zstd_level = 1};
};

struct ImportReport {
  InputSummary input;
  std::map<Role, uint64_t> messages;  // imported per role
  uint64_t events = 0;
  int64_t first_ns = 0, last_ns = 0;  // event stamps
  std::vector<std::string> warnings;  // e.g. a truncated input
};

// Imports `in` into the fixture `out`. Errors name the input file, the topic, the message
// (index and byte offset) and the field: a mapped topic of a type no role converter
// reads, a required role without a topic, a message that contradicts itself (image size
// vs num_ranges x num_beams, bearings count), a stamp outside the ROS time range.
// A truncated input is imported up to its last complete chunk, with a warning.
Result<ImportReport> import_recording(const std::string& in, const std::string& out, const ImportOptions& options);

// "sensor_msgs/msg/Imu" -> "sensor_msgs/Imu".
std::string normalise_type(const std::string& type);

}  // namespace orthosonar::replay::ros
