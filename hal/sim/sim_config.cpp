#include "hal/sim/sim_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace orthosonar::sim {

const char* resolution_name(Resolution r) { return r == Resolution::kFull ? "full" : "reduced"; }

Result<Resolution> parse_resolution(const std::string& s) {
  if (s == "full") return Resolution::kFull;
  if (s == "reduced") return Resolution::kReduced;
  return Error{"resolution '" + s + "' is neither 'full' nor 'reduced'"};
}

SonarGeometry sonar_geometry(const SonarModelConfig& c, Resolution r) {
  SonarGeometry g;
  const int div = r == Resolution::kFull ? 1 : 2;
  g.beams = c.beams_full / div;
  g.range_bins = c.range_bins_full / div;
  g.range_resolution_m = c.max_range_m / g.range_bins;
  return g;
}

namespace {

// One settable field: a name and a setter from a YAML scalar.
using Setter = std::function<void(const YAML::Node&)>;
template <class T>
Setter set(T& field) {
  return [&field](const YAML::Node& n) { field = n.as<T>(); };
}

std::map<std::string, Setter> sonar_fields(SonarModelConfig& s) {
  return {{"max_range_m", set(s.max_range_m)}, {"beams_full", set(s.beams_full)},
          {"range_bins_full", set(s.range_bins_full)}, {"swath_deg", set(s.swath_deg)},
          {"aperture_deg", set(s.aperture_deg)}, {"bearing_cubic", set(s.bearing_cubic)},
          {"elevation_samples", set(s.elevation_samples)}, {"beam_samples", set(s.beam_samples)},
          {"beam_width_factor", set(s.beam_width_factor)},
          {"aperture_sigma_deg", set(s.aperture_sigma_deg)},
          {"incidence_exponent", set(s.incidence_exponent)},
          {"spreading_exponent", set(s.spreading_exponent)},
          {"speckle_looks", set(s.speckle_looks)}, {"noise_floor", set(s.noise_floor)},
          {"tvg_exponent", set(s.tvg_exponent)}, {"tvg_reference_m", set(s.tvg_reference_m)},
          {"gain", set(s.gain)}, {"gamma", set(s.gamma)}, {"gain_percent", set(s.gain_percent)},
          {"frequency_h_hz", set(s.frequency_h_hz)}, {"frequency_v_hz", set(s.frequency_v_hz)},
          {"reflectivity", [&s](const YAML::Node& n) {
             for (const auto& kv : n) {
               for (int c = 0; c < kSemanticClassCount; ++c) {
                 if (kv.first.as<std::string>() == semantic_class_name(static_cast<SemanticClass>(c))) {
                   s.reflectivity[static_cast<size_t>(c)] = kv.second.as<double>();
                 }
               }
             }
           }}};
}

std::map<std::string, Setter> vehicle_fields(VehicleConfig& v) {
  return {{"speed_mps", set(v.speed_mps)}, {"max_yaw_rate_dps", set(v.max_yaw_rate_dps)},
          {"yaw_gain_per_s", set(v.yaw_gain_per_s)},
          {"acceptance_radius_m", set(v.acceptance_radius_m)},
          {"slow_turn_factor", set(v.slow_turn_factor)},
          {"roll_amplitude_deg", set(v.roll_amplitude_deg)},
          {"pitch_amplitude_deg", set(v.pitch_amplitude_deg)},
          {"roll_period_s", set(v.roll_period_s)}, {"pitch_period_s", set(v.pitch_period_s)},
          {"current_x_mps", set(v.current_x_mps)}, {"current_y_mps", set(v.current_y_mps)},
          {"step_s", set(v.step_s)}};
}

std::map<std::string, Setter> nav_fields(NavConfig& n) {
  return {{"imu_rate_hz", set(n.imu_rate_hz)}, {"dvl_rate_hz", set(n.dvl_rate_hz)},
          {"depth_rate_hz", set(n.depth_rate_hz)}, {"ping_rate_hz", set(n.ping_rate_hz)},
          {"ping_offset_s", set(n.ping_offset_s)}, {"vertical_delay_s", set(n.vertical_delay_s)},
          {"dvl_offset_s", set(n.dvl_offset_s)}, {"depth_offset_s", set(n.depth_offset_s)},
          {"dvl_sigma_mps", set(n.dvl_sigma_mps)},
          {"dvl_invalid_probability", set(n.dvl_invalid_probability)},
          {"dvl_max_altitude_m", set(n.dvl_max_altitude_m)},
          {"imu_roll_pitch_sigma_deg", set(n.imu_roll_pitch_sigma_deg)},
          {"imu_yaw_sigma_deg", set(n.imu_yaw_sigma_deg)},
          {"imu_yaw_bias_walk_deg_per_sqrt_s", set(n.imu_yaw_bias_walk_deg_per_sqrt_s)},
          {"imu_yaw_bias_rate_dps", set(n.imu_yaw_bias_rate_dps)},
          {"imu_gyro_sigma_dps", set(n.imu_gyro_sigma_dps)},
          {"imu_gyro_bias_dps", set(n.imu_gyro_bias_dps)},
          {"depth_sigma_m", set(n.depth_sigma_m)}};
}

Status apply_fields(const YAML::Node& node, const std::map<std::string, Setter>& fields,
                    const std::string& where) {
  if (!node.IsMap()) return Error{"sim config: '" + where + "' must be a map"};
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) return Error{"sim config: a key in '" + where + "' is not a plain name"};
    const auto key = kv.first.as<std::string>();
    const auto it = fields.find(key);
    if (it == fields.end()) return Error{"sim config: unknown key '" + where + key + "'"};
    try {
      it->second(kv.second);
    } catch (const YAML::Exception& e) {
      return Error{"sim config: bad value for '" + where + key + "': " + e.what()};
    }
  }
  return Status::Ok();
}

}  // namespace

Status load_sim_config_file(const std::string& path, SimConfig& config) {
  std::ifstream in(path);
  if (!in) return Error{"cannot read simulator config '" + path + "'"};
  std::stringstream text;
  text << in.rdbuf();
  if (Status s = apply_sim_config_yaml(text.str(), config); !s.ok()) return Error{path + ": " + s.error().message};
  return {};
}

static Status apply_document(const std::string& yaml_text, SimConfig& c) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
  if (root.IsNull()) return Status::Ok();
  std::string resolution;
  std::string T_V_h, T_V_v;
  std::map<std::string, Setter> top = {
      {"duration_s", set(c.duration_s)}, {"seed", set(c.seed)}, {"labels", set(c.labels)},
      {"resolution", set(resolution)}, {"T_V_h", set(T_V_h)}, {"T_V_v", set(T_V_v)},
      {"device_id_h", set(c.device_id_h)}, {"device_id_v", set(c.device_id_v)},
      {"render_threads", set(c.render_threads)},
      {"sonar", [](const YAML::Node&) {}}, {"vehicle", [](const YAML::Node&) {}},
      {"nav", [](const YAML::Node&) {}}};
  if (auto s = apply_fields(root, top, ""); !s) return s;
  if (root["sonar"]) {
    if (auto s = apply_fields(root["sonar"], sonar_fields(c.sonar), "sonar."); !s) return s;
  }
  if (root["vehicle"]) {
    if (auto s = apply_fields(root["vehicle"], vehicle_fields(c.vehicle), "vehicle."); !s) return s;
  }
  if (root["nav"]) {
    if (auto s = apply_fields(root["nav"], nav_fields(c.nav), "nav."); !s) return s;
  }
  if (!resolution.empty()) {
    auto r = parse_resolution(resolution);
    if (!r) return r.error();
    c.resolution = *r;
  }
  for (auto [text, T] : {std::pair{&T_V_h, &c.T_V_h}, std::pair{&T_V_v, &c.T_V_v}}) {
    if (text->empty()) continue;
    auto p = parse_pose6(*text);
    if (!p) return p.error();
    *T = *p;
  }
  return validate(c);
}

Status apply_sim_config_yaml(const std::string& yaml_text, SimConfig& c) {
  // Every setter checks its node; this is the net under them (found by fuzz_sim_config: a
  // '? :' key threw yaml-cpp's TypedBadConversion through the API).
  try {
    return apply_document(yaml_text, c);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
}

Status validate(const SimConfig& c) {
  const auto& s = c.sonar;
  if (!(c.duration_s > 0)) return Error{"sim config: duration_s must be > 0"};
  if (s.elevation_samples < 32) return Error{"sim config: sonar.elevation_samples must be >= 32"};
  if (s.beam_samples < 1) return Error{"sim config: sonar.beam_samples must be >= 1"};
  if (s.beams_full < 4 || s.beams_full % 2 != 0 || s.range_bins_full < 4 || s.range_bins_full % 2 != 0)
    return Error{"sim config: beams_full and range_bins_full must be even and >= 4"};
  if (s.speckle_looks < 1 || s.speckle_looks > 16) return Error{"sim config: sonar.speckle_looks in 1..16"};
  if (!(s.max_range_m > 0 && s.gamma > 0 && s.gain > 0)) return Error{"sim config: sonar max_range_m, gamma, gain must be > 0"};
  const auto& n = c.nav;
  for (double r : {n.imu_rate_hz, n.dvl_rate_hz, n.depth_rate_hz, n.ping_rate_hz}) {
    if (!(r > 0 && r <= 1000)) return Error{"sim config: sensor rates must be in (0, 1000] Hz"};
  }
  if (!(n.vertical_delay_s >= 0 && n.vertical_delay_s < 1.0 / n.ping_rate_hz))
    return Error{"sim config: nav.vertical_delay_s must be in [0, ping period)"};
  if (!(c.vehicle.speed_mps > 0 && c.vehicle.step_s > 0 && c.vehicle.max_yaw_rate_dps > 0))
    return Error{"sim config: vehicle speed, step and yaw rate must be > 0"};
  if (c.render_threads < 1 || c.render_threads > 64) return Error{"sim config: render_threads in 1..64"};
  return Status::Ok();
}

std::string format_pose6(const SE3& T) {
  const Vec3 t = T.translation();
  const Vec3 rpy = rpy_from_rotation(T.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", t.x(), t.y(), t.z(),
                rpy.x(), rpy.y(), rpy.z());
  return buf;
}

Result<SE3> parse_pose6(const std::string& s) {
  std::istringstream in(s);
  double v[6];
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) return Error{"pose '" + s + "': expected 'x y z roll pitch yaw'"};
  }
  std::string rest;
  if (in >> rest) return Error{"pose '" + s + "': trailing text '" + rest + "'"};
  return se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
}

}  // namespace orthosonar::sim
