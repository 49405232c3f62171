#pragma once
// Which topics of a ROS recording feed which sensor role, and how (topics.yaml; the
// format is in docs/IMPORT.md). Without a file, the authors' topics are mapped
// (default_topic_map); a file adds or overrides topics and sets mounts.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::replay::ros {

// kGyro: a fibre-optic gyro's delta angles (optional, as kTruth); last, so the others keep their values.
enum class Role : uint8_t { kHorizontalSonar, kVerticalSonar, kImu, kDvl, kDepth, kTruth, kGyro };
inline constexpr Role kRequiredRoles[] = {Role::kHorizontalSonar, Role::kVerticalSonar, Role::kImu, Role::kDvl,
                                          Role::kDepth};
std::string_view role_name(Role r);                  // "horizontal_sonar", ...
std::optional<Role> role_from_name(std::string_view name);
Channel channel_for(Role r);

enum class StampSource : uint8_t { kHeader, kReceive };
// Axis convention of a navigation topic: ROS REP-103 (world ENU, body x forward y left z
// up: ours) or NED / FRD (many IMU and DVL drivers publish it).
enum class Convention : uint8_t { kEnuFlu, kNedFrd };

struct TopicRule {
  std::string topic;
  Role role = Role::kImu;
  StampSource stamp = StampSource::kHeader;
  Convention convention = Convention::kEnuFlu;
  // Sonars.
  uint32_t device_id = 0;            // not carried by the ROS types
  uint16_t part_number = 0;          // 0: from the message, else M750d (h) / M1200d (v)
  bool flip_bearings = false;        // negate bearings (a sonar mounted upside down, or the other sign convention)
  // Depth from sensor_msgs/FluidPressure: depth = (p - atmospheric) / (density * gravity).
  double fluid_density_kg_m3 = 1025.0;
  double atmospheric_pressure_pa = 101325.0;
  double gravity_m_s2 = 9.80665;
  // Added by default_topic_map (not listed in a topics.yaml): a default topic of an optional
  // role (truth, gyro) whose type that role cannot read is skipped with a warning, not an error.
  bool from_defaults = false;
};

struct TopicMap {
  std::vector<TopicRule> rules;           // explicit ones first; the first rule for a topic wins
  // Sonar extrinsics written into the fixture's metadata ("x y z roll pitch yaw", metres
  // and radians, as fixtures store them); empty: the run configuration's defaults apply.
  std::string T_V_h, T_V_v;
  // The fibre-optic gyro's mounting T_V_gyro (same form) and the latitude of the survey in
  // degrees, [-90, 90] (the Earth rate the gyro senses): fixture metadata T_V_gyro and
  // latitude_deg; empty / none: the run configuration's dr.T_V_gyro and dr.latitude_deg.
  std::string T_V_gyro;
  std::optional<double> latitude_deg;
  std::string source;                     // the file the map came from ("" = built in)
  const TopicRule* find(std::string_view topic) const;
};

// The authors' stack: /sonar_oculus_node/M750d/ping (h), /sonar_oculus_node/M1200d/ping
// (v), /vn100/imu/raw, /rti/body_velocity/raw, /bar30/depth/raw, /gyro (kvh_gyro/gyro),
// and /orthosonar/truth (what `orthosonar export` writes); header stamps, REP-103 axes.
TopicMap default_topic_map();

// Parses topics.yaml (text); `path` names the file in errors. Unless it says
// `defaults: false`, the default topics follow its own.
Result<TopicMap> parse_topic_map(const std::string& yaml_text, const std::string& path);
Result<TopicMap> load_topic_map(const std::string& path);

// topics.yaml text describing `map` (explicit rules and mounts), parseable by parse_topic_map.
std::string topic_map_yaml(const TopicMap& map, bool defaults);

}  // namespace orthosonar::replay::ros
