#include "hal/drivers/device_config.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace orthosonar::hal::drivers {
namespace {

Quat from_rpy_deg(double r, double p, double y) {
  const double d = 3.14159265358979323846 / 180.0;
  return Quat(Eigen::AngleAxisd(y * d, Vec3::UnitZ()) * Eigen::AngleAxisd(p * d, Vec3::UnitY()) *
              Eigen::AngleAxisd(r * d, Vec3::UnitX()));
}

Vec3 rpy_deg(const Quat& q) { return rpy_from_rotation(q.toRotationMatrix()) * (180.0 / 3.14159265358979323846); }

}  // namespace

const char* kind_name(DeviceKind k) {
  switch (k) {
    case DeviceKind::kOculus: return "oculus";
    case DeviceKind::kVn100: return "vn100";
    case DeviceKind::kA50: return "a50";
    case DeviceKind::kPrti01: return "prti01";
    case DeviceKind::kDepth: return "depth";
    case DeviceKind::kRtiEnsemble: return "rti-ensemble";
    case DeviceKind::kDsp1760: return "dsp1760";
  }
  return "?";
}

Result<DeviceKind> kind_from_name(const std::string& s) {
  for (DeviceKind k : {DeviceKind::kOculus, DeviceKind::kVn100, DeviceKind::kA50, DeviceKind::kPrti01, DeviceKind::kDepth,
                      DeviceKind::kDsp1760})
    if (s == kind_name(k)) return k;
  if (s == kind_name(DeviceKind::kRtiEnsemble)) return DeviceKind::kRtiEnsemble;
  return Error{"unknown device kind '" + s + "' (oculus, vn100, a50, prti01, depth, dsp1760, rti-ensemble)"};
}

// Every key of a map must be one this file reads: a misspelt key (`silence_timout_ms`,
// `mount_rpy` on the IMU) is an error naming it, never a default silently kept.
static Status device_config_known_keys(const YAML::Node& n, const std::string& where, std::initializer_list<const char*> keys) {
  if (!n.IsMap()) return Error{"devices.yaml: '" + where + "' must be a map"};
  for (const auto& kv : n) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<not a plain name>");
    bool known = false;
    for (const char* k : keys) known = known || key == k;
    if (!known) {
      std::string list;
      for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
      return Error{"devices.yaml: unknown key '" + key + "' in " + where + " (known: " + list + ")"};
    }
  }
  return {};
}

Result<LiveConfig> parse_live_config(const std::string& text) {
  LiveConfig c;
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) return Error{"devices.yaml: the document must be a map with 'devices'"};
    if (auto s = device_config_known_keys(root, "the document", {"queue", "reconnect", "devices"}); !s) return s.error();
    if (const auto q = root["queue"]) {
      if (auto s = device_config_known_keys(q, "queue", {"sonar_capacity", "nav_capacity"}); !s) return s.error();
      c.queue.sonar_capacity = q["sonar_capacity"].as<size_t>(c.queue.sonar_capacity);
      c.queue.nav_capacity = q["nav_capacity"].as<size_t>(c.queue.nav_capacity);
    }
    if (const auto r = root["reconnect"]) {
      if (auto s = device_config_known_keys(
              r, "reconnect", {"initial_backoff_ms", "max_backoff_ms", "connect_timeout_ms", "silence_timeout_ms"});
          !s)
        return s.error();
      c.reconnect.initial_backoff_ms = r["initial_backoff_ms"].as<int64_t>(c.reconnect.initial_backoff_ms);
      c.reconnect.max_backoff_ms = r["max_backoff_ms"].as<int64_t>(c.reconnect.max_backoff_ms);
      c.reconnect.connect_timeout_ms = r["connect_timeout_ms"].as<int64_t>(c.reconnect.connect_timeout_ms);
      c.reconnect.silence_timeout_ms = r["silence_timeout_ms"].as<int64_t>(c.reconnect.silence_timeout_ms);
    }
    const auto devs = root["devices"];
    if (!devs || !devs.IsSequence()) return Error{"devices.yaml: 'devices' must be a list"};
    for (const auto& n : devs) {
      DeviceConfig d;
      d.name = n["name"].as<std::string>("");
      if (d.name.empty()) return Error{"devices.yaml: a device has no 'name'"};
      auto kind = kind_from_name(n["kind"].as<std::string>(""));
      if (!kind) return Error{"devices.yaml: device '" + d.name + "': " + kind.error().message};
      d.kind = *kind;
      const std::string where = "device '" + d.name + "'";
      if (d.kind == DeviceKind::kOculus) {
        if (auto s = device_config_known_keys(n, where, {"name", "kind", "address", "port", "serial", "baud", "mount",
                                                         "part_number", "status_port", "fire", "mount_rpy_deg"});
            !s)
          return s.error();
      } else if (d.kind == DeviceKind::kDsp1760) {
        // No mount_rpy_deg: a gyro's readings stay in its frame G (the run configuration mounts it).
        if (auto s = device_config_known_keys(n, where + " (dsp1760)", {"name", "kind", "address", "port", "serial", "baud",
                                                                         "output", "angle_units", "temperature_units"});
            !s)
          return s.error();
      } else if (auto s = device_config_known_keys(n, where + " (" + kind_name(d.kind) + ")",
                                                   {"name", "kind", "address", "port", "serial", "baud", "mount_rpy_deg"});
                 !s) {
        return s.error();
      }
      d.address = n["address"].as<std::string>(d.address);
      d.port = n["port"].as<uint16_t>(d.kind == DeviceKind::kOculus ? oculus::kTcpPort : 0);
      d.serial_path = n["serial"].as<std::string>("");
      d.baud = n["baud"].as<int>(d.kind == DeviceKind::kDsp1760 ? 921600 : d.baud);
      if (d.port == 0 && d.serial_path.empty()) return Error{"devices.yaml: device '" + d.name + "' needs 'port' or 'serial'"};
      if (d.kind == DeviceKind::kOculus) {
        const std::string mount = n["mount"].as<std::string>("horizontal");
        if (mount != "horizontal" && mount != "vertical")
          return Error{"devices.yaml: device '" + d.name + "': mount must be horizontal or vertical"};
        d.mount = mount == "vertical" ? SonarMount::kVertical : SonarMount::kHorizontal;
        d.part_number = n["part_number"].as<uint16_t>(0);
        d.status_port = n["status_port"].as<uint16_t>(d.status_port);
        d.listen_status = d.status_port != 0;  // status_port: 0 disables the listener
        if (const auto f = n["fire"]) {
          if (auto s = device_config_known_keys(f, where + " fire", {"version", "range_m", "gain_percent", "gamma", "mode",
                                                                     "ping_rate", "bits", "beams", "send_gain"});
              !s)
            return s.error();
          d.fire_version = f["version"].as<int>(2);
          if (d.fire_version != 1 && d.fire_version != 2) return Error{"devices.yaml: device '" + d.name + "': fire.version must be 1 or 2"};
          d.fire.range = f["range_m"].as<double>(d.fire.range);
          d.fire.gain_percent = f["gain_percent"].as<double>(d.fire.gain_percent);
          d.fire.gamma = static_cast<uint8_t>(f["gamma"].as<int>(d.fire.gamma));
          d.fire.master_mode = static_cast<uint8_t>(f["mode"].as<int>(d.fire.master_mode));
          d.fire.ping_rate = static_cast<uint8_t>(f["ping_rate"].as<int>(d.fire.ping_rate));
          const int bits = f["bits"].as<int>(8);
          const int beams = f["beams"].as<int>(512);
          if (bits != 8 && bits != 16) return Error{"devices.yaml: device '" + d.name + "': fire.bits must be 8 or 16"};
          if (beams != 256 && beams != 512) return Error{"devices.yaml: device '" + d.name + "': fire.beams must be 256 or 512"};
          d.fire.flags = static_cast<uint8_t>(oculus::kFlagRangeAsMeters | oculus::kFlagSimpleReturn |
                                              (bits == 16 ? oculus::kFlagData16Bit : 0) |
                                              (beams == 512 ? oculus::kFlag512Beams : 0) |
                                              (f["send_gain"].as<bool>(false) ? oculus::kFlagSendGain : 0));
        }
      }
      if (d.kind == DeviceKind::kDsp1760) {
        // What the gyro was configured to send (=dr output, units, =tempunits): not in its packets.
        auto out = dsp1760::output_from_name(n["output"].as<std::string>("delta"));
        if (!out) return Error{"devices.yaml: " + where + ": output: " + out.error().message};
        auto ang = dsp1760::angle_unit_from_name(n["angle_units"].as<std::string>("rad"));
        if (!ang) return Error{"devices.yaml: " + where + ": angle_units: " + ang.error().message};
        auto tmp = dsp1760::temperature_unit_from_name(n["temperature_units"].as<std::string>("c"));
        if (!tmp) return Error{"devices.yaml: " + where + ": temperature_units: " + tmp.error().message};
        d.gyro.output = *out;
        d.gyro.angle_unit = *ang;
        d.gyro.temperature_unit = *tmp;
      }
      if (const auto m = n["mount_rpy_deg"]) {
        if (!m.IsSequence() || m.size() != 3) return Error{"devices.yaml: device '" + d.name + "': mount_rpy_deg needs 3 numbers"};
        const double r = m[0].as<double>(), p = m[1].as<double>(), y = m[2].as<double>();
        // The mount turns every IMU quaternion of the device: a NaN here is a NaN orientation.
        if (!std::isfinite(r) || !std::isfinite(p) || !std::isfinite(y))
          return Error{"devices.yaml: device '" + d.name + "': mount_rpy_deg must be 3 finite numbers"};
        d.q_V_S = from_rpy_deg(r, p, y);
      } else if (d.kind == DeviceKind::kA50) {
        d.q_V_S = Quat(0.0, 1.0, 0.0, 0.0);  // A50 frame x forward, y right, z down
      }
      c.devices.push_back(d);
    }
  } catch (const YAML::Exception& e) {
    return Error{std::string("devices.yaml: ") + e.what()};
  }
  return c;
}

Result<LiveConfig> load_live_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"cannot open '" + path + "'"};
  std::stringstream ss;
  ss << in.rdbuf();
  auto c = parse_live_config(ss.str());
  if (!c) return Error{path + ": " + c.error().message};
  return c;
}

std::string to_yaml(const LiveConfig& c) {
  std::ostringstream o;
  o << "queue: {sonar_capacity: " << c.queue.sonar_capacity << ", nav_capacity: " << c.queue.nav_capacity << "}\n";
  o << "reconnect: {initial_backoff_ms: " << c.reconnect.initial_backoff_ms << ", max_backoff_ms: " << c.reconnect.max_backoff_ms
    << ", connect_timeout_ms: " << c.reconnect.connect_timeout_ms << ", silence_timeout_ms: " << c.reconnect.silence_timeout_ms << "}\n";
  o << "devices:\n";
  for (const auto& d : c.devices) {
    o << "  - name: " << d.name << "\n    kind: " << kind_name(d.kind) << "\n";
    if (!d.serial_path.empty()) {
      o << "    serial: " << d.serial_path << "\n    baud: " << d.baud << "\n";
    } else {
      o << "    address: " << d.address << "\n    port: " << d.port << "\n";
    }
    if (d.kind == DeviceKind::kOculus) {
      o << "    mount: " << (d.mount == SonarMount::kVertical ? "vertical" : "horizontal") << "\n";
      o << "    part_number: " << d.part_number << "\n    status_port: " << (d.listen_status ? d.status_port : 0) << "\n";
      o << "    fire: {version: " << d.fire_version << ", range_m: " << d.fire.range << ", gain_percent: " << d.fire.gain_percent
        << ", gamma: " << int(d.fire.gamma) << ", mode: " << int(d.fire.master_mode)
        << ", bits: " << ((d.fire.flags & oculus::kFlagData16Bit) ? 16 : 8)
        << ", beams: " << ((d.fire.flags & oculus::kFlag512Beams) ? 512 : 256) << "}\n";
    } else if (d.kind == DeviceKind::kDsp1760) {
      o << "    output: " << dsp1760::output_name(d.gyro.output) << "\n    angle_units: "
        << dsp1760::angle_unit_name(d.gyro.angle_unit) << "\n    temperature_units: "
        << dsp1760::temperature_unit_name(d.gyro.temperature_unit) << "\n";
    } else {
      const Vec3 r = rpy_deg(d.q_V_S);
      o << "    mount_rpy_deg: [" << r.x() << ", " << r.y() << ", " << r.z() << "]\n";
    }
  }
  return o.str();
}

}  // namespace orthosonar::hal::drivers
