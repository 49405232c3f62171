#include "replay/ros/topic_map.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "hal/config/pose6.hpp"

namespace orthosonar::replay::ros {
namespace {

constexpr std::pair<Role, std::string_view> kRoleNames[] = {
    {Role::kHorizontalSonar, "horizontal_sonar"}, {Role::kVerticalSonar, "vertical_sonar"},
    {Role::kImu, "imu"}, {Role::kDvl, "dvl"}, {Role::kDepth, "depth"}, {Role::kTruth, "truth"},
    {Role::kGyro, "gyro"}};
constexpr const char* kRoleList = "horizontal_sonar, vertical_sonar, imu, dvl, depth, truth, gyro";

std::string fmt17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A YAML mapping's key as a plain name, or an error (a key like `? [a]` is not a name).
Result<std::string> key_name(const YAML::Node& key, const std::string& where) {
  if (!key.IsScalar()) return Error{where + ": a key that is not a plain name"};
  return key.Scalar();
}

Result<double> number(const YAML::Node& n, const std::string& where) {
  if (!n.IsScalar()) return Error{where + ": expected a number"};
  try {
    const double v = n.as<double>();
    if (!std::isfinite(v)) return Error{where + ": '" + n.Scalar() + "' is not a finite number"};
    return v;
  } catch (const YAML::Exception&) {
    return Error{where + ": '" + n.Scalar() + "' is not a number"};
  }
}

// "x y z roll pitch yaw" as fixture metadata stores extrinsics (lossless).
std::string pose6_text(const std::array<double, 6>& v) {
  std::string out;
  for (size_t i = 0; i < 6; ++i) out += (i ? " " : "") + fmt17(v[i]);
  return out;
}

// A mount: "x y z roll pitch yaw" (metres, radians) or {xyz: [x, y, z], rpy_deg: [r, p, y]}.
Result<std::string> mount(const YAML::Node& n, const std::string& where) {
  if (n.IsScalar()) {
    const config::Pose6Text p = config::read_pose6(n.Scalar());
    if (p.fault == config::Pose6Text::Fault::kNotSixFiniteNumbers)
      return Error{where + ": expected \"x y z roll pitch yaw\" (metres, radians)"};
    if (p.fault == config::Pose6Text::Fault::kTrailingText) return Error{where + ": more than six numbers"};
    return pose6_text(p.v);
  }
  if (!n.IsMap()) return Error{where + ": expected \"x y z roll pitch yaw\" or {xyz: [...], rpy_deg: [...]}"};
  std::array<double, 6> v = {0, 0, 0, 0, 0, 0};
  for (const auto& kv : n) {
    auto k = key_name(kv.first, where);
    if (!k) return k.error();
    const bool deg = *k == "rpy_deg";
    if (*k != "xyz" && *k != "rpy_deg" && *k != "rpy_rad")
      return Error{where + "." + *k + ": unknown key (xyz, rpy_deg, rpy_rad)"};
    if (!kv.second.IsSequence() || kv.second.size() != 3) return Error{where + "." + *k + ": expected three numbers"};
    for (size_t i = 0; i < 3; ++i) {
      auto x = number(kv.second[i], where + "." + *k + "[" + std::to_string(i) + "]");
      if (!x) return x.error();
      v[(*k == "xyz" ? 0 : 3) + i] = deg ? *x * std::numbers::pi / 180.0 : *x;
    }
  }
  return pose6_text(v);
}

Status apply_rule_key(TopicRule& r, const std::string& key, const YAML::Node& v, const std::string& where) {
  const std::string at = where + "." + key;
  auto text = [&]() -> Result<std::string> {
    if (!v.IsScalar()) return Error{at + ": expected a word"};
    return v.Scalar();
  };
  if (key == "role") {
    auto t = text();
    if (!t) return t.error();
    const auto role = role_from_name(*t);
    if (!role)
      return Error{at + ": unknown role '" + *t + "' (" + kRoleList + ")"};
    r.role = *role;
  } else if (key == "stamp") {
    auto t = text();
    if (!t) return t.error();
    if (*t == "header") r.stamp = StampSource::kHeader;
    else if (*t == "receive") r.stamp = StampSource::kReceive;
    else return Error{at + ": '" + *t + "' (header or receive)"};
  } else if (key == "convention") {
    auto t = text();
    if (!t) return t.error();
    if (*t == "enu_flu" || *t == "rep103") r.convention = Convention::kEnuFlu;
    else if (*t == "ned_frd") r.convention = Convention::kNedFrd;
    else return Error{at + ": '" + *t + "' (enu_flu or ned_frd)"};
  } else if (key == "flip_bearings") {
    auto t = text();
    if (!t) return t.error();
    if (*t == "true") r.flip_bearings = true;
    else if (*t == "false") r.flip_bearings = false;
    else return Error{at + ": '" + *t + "' (true or false)"};
  } else if (key == "device_id" || key == "part_number") {
    auto x = number(v, at);
    if (!x) return x.error();
    const double lim = key == "device_id" ? 4294967295.0 : 65535.0;
    if (*x < 0 || *x > lim || *x != std::floor(*x)) return Error{at + ": expected an integer 0.." + fmt17(lim)};
    if (key == "device_id") r.device_id = static_cast<uint32_t>(*x);
    else r.part_number = static_cast<uint16_t>(*x);
  } else if (key == "fluid_density" || key == "atmospheric_pressure" || key == "gravity") {
    auto x = number(v, at);
    if (!x) return x.error();
    if (*x <= 0 && key != "atmospheric_pressure") return Error{at + ": must be positive"};
    (key == "fluid_density" ? r.fluid_density_kg_m3 : key == "gravity" ? r.gravity_m_s2 : r.atmospheric_pressure_pa) = *x;
  } else {
    return Error{at + ": unknown key (role, stamp, convention, flip_bearings, device_id, part_number, "
                      "fluid_density, atmospheric_pressure, gravity)"};
  }
  return {};
}

Result<TopicMap> parse_root(const YAML::Node& root, const std::string& path) {
  TopicMap m;
  m.source = path;
  bool defaults = true;
  StampSource stamp = StampSource::kHeader;
  if (!root || root.IsNull()) return default_topic_map();
  if (!root.IsMap()) return Error{path + ": expected a mapping (topics:, mounts:, latitude_deg:, defaults:, stamp:)"};
  for (const auto& kv : root) {
    auto k = key_name(kv.first, path);
    if (!k) return k.error();
    if (*k == "defaults") {
      if (!kv.second.IsScalar() || (kv.second.Scalar() != "true" && kv.second.Scalar() != "false"))
        return Error{path + ": defaults: expected true or false"};
      defaults = kv.second.Scalar() == "true";
    } else if (*k == "stamp") {
      if (!kv.second.IsScalar() || (kv.second.Scalar() != "header" && kv.second.Scalar() != "receive"))
        return Error{path + ": stamp: expected header or receive"};
      stamp = kv.second.Scalar() == "header" ? StampSource::kHeader : StampSource::kReceive;
    }
  }
  std::set<std::string> seen;
  for (const auto& kv : root) {
    const std::string k = kv.first.Scalar();
    if (k == "defaults" || k == "stamp") continue;
    if (k == "topics") {
      if (!kv.second.IsMap()) return Error{path + ": topics: expected a mapping topic -> {role: ...}"};
      for (const auto& t : kv.second) {
        auto topic = key_name(t.first, path + ": topics");
        if (!topic) return topic.error();
        const std::string where = path + ": topics." + *topic;
        if (topic->empty()) return Error{where + ": empty topic name"};
        if (!seen.insert(*topic).second) return Error{where + ": listed twice"};
        TopicRule r;
        r.topic = *topic;
        r.stamp = stamp;
        bool has_role = false;
        if (t.second.IsScalar()) {  // shorthand: "/imu/data: imu"
          if (auto s = apply_rule_key(r, "role", t.second, where); !s) return s.error();
          has_role = true;
        } else if (t.second.IsMap()) {
          for (const auto& f : t.second) {
            auto key = key_name(f.first, where);
            if (!key) return key.error();
            if (auto s = apply_rule_key(r, *key, f.second, where); !s) return s.error();
            has_role = has_role || *key == "role";
          }
        } else {
          return Error{where + ": expected a role or a mapping {role: ..., ...}"};
        }
        if (!has_role) return Error{where + ": no role (" + kRoleList + ")"};
        m.rules.push_back(r);
      }
    } else if (k == "mounts") {
      if (!kv.second.IsMap()) return Error{path + ": mounts: expected {horizontal: ..., vertical: ..., gyro: ...}"};
      for (const auto& t : kv.second) {
        auto name = key_name(t.first, path + ": mounts");
        if (!name) return name.error();
        if (*name != "horizontal" && *name != "vertical" && *name != "gyro")
          return Error{path + ": mounts." + *name + ": unknown mount (horizontal, vertical, gyro)"};
        auto text = mount(t.second, path + ": mounts." + *name);
        if (!text) return text.error();
        (*name == "horizontal" ? m.T_V_h : *name == "vertical" ? m.T_V_v : m.T_V_gyro) = *text;
      }
    } else if (k == "latitude_deg") {
      auto lat = number(kv.second, path + ": latitude_deg");
      if (!lat) return lat.error();
      if (*lat < -90.0 || *lat > 90.0)
        return Error{path + ": latitude_deg: " + fmt17(*lat) + " is not a latitude in [-90, 90] degrees"};
      m.latitude_deg = *lat;
    } else {
      return Error{path + ": unknown key '" + k + "' (topics, mounts, latitude_deg, defaults, stamp)"};
    }
  }
  if (defaults) {
    for (TopicRule r : default_topic_map().rules) {
      if (m.find(r.topic) != nullptr) continue;
      r.stamp = stamp;
      m.rules.push_back(r);
    }
  }
  return m;
}

}  // namespace

std::string_view role_name(Role r) {
  for (const auto& [role, name] : kRoleNames)
    if (role == r) return name;
  return "?";
}

std::optional<Role> role_from_name(std::string_view name) {
  for (const auto& [role, n] : kRoleNames)
    if (n == name) return role;
  return std::nullopt;
}

Channel channel_for(Role r) {
  switch (r) {
    case Role::kHorizontalSonar: return Channel::kSonarHorizontal;
    case Role::kVerticalSonar: return Channel::kSonarVertical;
    case Role::kImu: return Channel::kImu;
    case Role::kDvl: return Channel::kDvl;
    case Role::kDepth: return Channel::kDepth;
    case Role::kTruth: return Channel::kTruthPose;
    case Role::kGyro: return Channel::kGyro;
  }
  return Channel::kImu;
}

const TopicRule* TopicMap::find(std::string_view topic) const {
  for (const auto& r : rules)
    if (r.topic == topic) return &r;
  return nullptr;
}

TopicMap default_topic_map() {
  TopicMap m;
  auto add = [&](const char* topic, Role role) {
    TopicRule r;
    r.topic = topic;
    r.role = role;
    r.from_defaults = true;
    m.rules.push_back(r);
  };
  add("/sonar_oculus_node/M750d/ping", Role::kHorizontalSonar);
  add("/sonar_oculus_node/M1200d/ping", Role::kVerticalSonar);
  add("/vn100/imu/raw", Role::kImu);
  add("/rti/body_velocity/raw", Role::kDvl);
  add("/bar30/depth/raw", Role::kDepth);
  add("/orthosonar/truth", Role::kTruth);
  add("/gyro", Role::kGyro);  // kvh_gyro/gyro, as the authors' gyro_node publishes it
  return m;
}

Result<TopicMap> parse_topic_map(const std::string& yaml_text, const std::string& path) {
  try {
    return parse_root(YAML::Load(yaml_text), path);
  } catch (const YAML::Exception& e) {
    return Error{path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

Result<TopicMap> load_topic_map(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::ostringstream s;
  s << in.rdbuf();
  return parse_topic_map(s.str(), path);
}

std::string topic_map_yaml(const TopicMap& map, bool defaults) {
  std::string y = "# topics.yaml (docs/IMPORT.md): topic -> sensor role, mounts\n";
  y += std::string("defaults: ") + (defaults ? "true" : "false") + "\n";
  y += "topics:\n";
  const TopicRule base;
  for (const auto& r : map.rules) {
    y += "  " + r.topic + ":\n    role: " + std::string(role_name(r.role)) + "\n";
    y += std::string("    stamp: ") + (r.stamp == StampSource::kHeader ? "header" : "receive") + "\n";
    if (r.convention == Convention::kNedFrd) y += "    convention: ned_frd\n";
    if (r.device_id != 0) y += "    device_id: " + std::to_string(r.device_id) + "\n";
    if (r.part_number != 0) y += "    part_number: " + std::to_string(r.part_number) + "\n";
    if (r.flip_bearings) y += "    flip_bearings: true\n";
    if (r.role == Role::kDepth) {
      if (r.fluid_density_kg_m3 != base.fluid_density_kg_m3) y += "    fluid_density: " + fmt17(r.fluid_density_kg_m3) + "\n";
      if (r.atmospheric_pressure_pa != base.atmospheric_pressure_pa)
        y += "    atmospheric_pressure: " + fmt17(r.atmospheric_pressure_pa) + "\n";
      if (r.gravity_m_s2 != base.gravity_m_s2) y += "    gravity: " + fmt17(r.gravity_m_s2) + "\n";
    }
  }
  if (!map.T_V_h.empty() || !map.T_V_v.empty() || !map.T_V_gyro.empty()) {
    y += "mounts:   # x y z roll pitch yaw (metres, radians): T_V_h, T_V_v, T_V_gyro\n";
    if (!map.T_V_h.empty()) y += "  horizontal: \"" + map.T_V_h + "\"\n";
    if (!map.T_V_v.empty()) y += "  vertical: \"" + map.T_V_v + "\"\n";
    if (!map.T_V_gyro.empty()) y += "  gyro: \"" + map.T_V_gyro + "\"\n";
  }
  if (map.latitude_deg) y += "latitude_deg: " + fmt17(*map.latitude_deg) + "   # the survey's (the gyro's Earth rate)\n";
  return y;
}

}  // namespace orthosonar::replay::ros
