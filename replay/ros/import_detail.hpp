#pragma once
// Internal to orthosonar_ros: what the parts of `orthosonar import` share: the recording (a bag
// or an MCAP file) and its messages (import_recording.cpp), the readable types and the
// per-message conversion (import_convert.cpp), used by the two passes (import.cpp).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <string_view>

#include "replay/ros/import.hpp"
#include "replay/ros/ros_msg.hpp"

namespace orthosonar::replay::ros::detail {

using rosmsg::Value;

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr int64_t kNsPerS = 1'000'000'000;

// ---- The recording: a bag or an MCAP file, visited in file order (import_recording.cpp) ----

struct SrcChannel {
  std::string topic, type, definition;
  rosmsg::Dialect dialect = rosmsg::Dialect::kRos1;
  rosmsg::Encoding encoding = rosmsg::Encoding::kRos1;
  std::string encoding_name;  // as the file says
  std::string unusable;       // why its messages cannot be decoded ("" when they can)
};

struct SrcMessage {
  uint32_t channel = 0;
  uint64_t receive_ns = 0;
  const uint8_t* data = nullptr;
  size_t size = 0;
  uint64_t chunk_offset = 0, offset = 0;
};

using OnChannel = std::function<Status(uint32_t, const SrcChannel&)>;
using OnMessage = std::function<Status(const SrcMessage&)>;

struct Recording {
  std::string path, format;
  uint64_t bytes = 0;
  bool complete = true;
  std::string recovery;

  // Visits the whole file (again from the start on every call).
  Status visit(const OnChannel& on_channel, const OnMessage& on_message);
};

// The recording at `path` by its first bytes: a ROS 1 bag (format 2.0) or an MCAP file.
Result<Recording> open_recording(const std::string& path);
// A message's place for an error: the file, the topic, the message's index, its byte offset.
std::string where(const Recording& rec, const SrcChannel& c, uint64_t index, const SrcMessage& m);

// ---- Readable types and the conversion of one message (import_convert.cpp) ----------------

enum class Kind { kOculusPing, kOculusPingRaw, kProjected, kImu, kRtiDvl, kTwistCov, kTwist, kBar30, kPressure,
                  kPose, kOdometry, kKvhGyro };

struct TypeEntry {
  std::string_view type;
  Kind kind;
  Role roles[2];  // the roles it can feed (second = first when only one)
};
// The readable type `type` (nullptr: none).
const TypeEntry* type_entry(const std::string& type);
// Why `type` cannot feed `role` ("" when it can).
std::string check_type(Role role, const std::string& type);
// One decoded message of a readable kind as the fixture's payload; `at` names it in errors.
Result<Payload> convert(Kind kind, const Value& msg, const TopicRule& rule, int64_t stamp_ns, const std::string& at);

}  // namespace orthosonar::replay::ros::detail
